// The cost of the ParaView output (run by hand: build/bench/bench_output [repeats] [divisions] [folder];
// the table of docs/output.md). SDNV104's elastic QUAD4 shoe, 40 × 40 elements by default, step 0.01 s
// to 4 s with the scene's output rate (0.01 s: a frame every step, 401 frames), run whole (run_scene
// into FOLDER/csim-bench-output, default /tmp; a folder for each run, deleted at the end) with
// output.paraview = none, ascii, binary and zlib in turn, alternating, `repeats` times each. Printed:
// the median wall time of each with its spread (min–max), the share of the run spent on ParaView
// output, (t − t_none) / t of the medians, the median CPU time of the process (user + system, every
// thread: the files are written by a thread of their own) and its share likewise, and the bytes
// written per run. Then the zlib levels on the same frames: the per-frame arrays of the binary
// run's files (displacement, velocity, stress, von Mises, pressure), compressed in VTK's 32 KiB blocks
// at each level (and level 1 with zlib's run-length and Huffman-only strategies), time and size.
#include "tools/run/run.h"
#include "tools/scene/scene.h"

#include <sys/resource.h>
#include <zlib.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double cpu_seconds() {  // user + system, every thread of the process
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_utime.tv_sec + usage.ru_stime.tv_sec + 1e-6 * (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::uintmax_t folder_bytes(const fs::path& folder) {
  std::uintmax_t bytes = 0;
  if (fs::exists(folder))
    for (const auto& entry : fs::directory_iterator(folder)) bytes += entry.file_size();
  return bytes;
}

// The appended arrays of an uncompressed (binary) file, each as its bytes, in file order.
std::vector<std::string> appended_arrays(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  std::size_t at = s.find('_', s.find("<AppendedData")) + 1;
  const std::size_t end = s.rfind("\n  </AppendedData>");
  std::vector<std::string> arrays;
  while (at < end) {
    std::uint64_t size;
    std::memcpy(&size, s.data() + at, 8);
    arrays.push_back(s.substr(at + 8, size));
    at += 8 + size;
  }
  return arrays;
}

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::atoi(argv[1]) : 5;
  const int divisions = argc > 2 ? std::atoi(argv[2]) : 40;
  const std::string scene_file = CSIM_SOURCE_DIR "/scenes/sdnv104-quad4/scene.yaml";
  const fs::path root = fs::path(argc > 3 ? argv[3] : fs::temp_directory_path().string()) / "csim-bench-output";
  const std::vector<std::string> encodings{"none", "ascii", "binary", "zlib"};
  fs::remove_all(root);
  std::map<std::string, std::vector<double>> seconds, cpu;
  std::map<std::string, std::uintmax_t> bytes;
  std::size_t frames = 0;
  for (int r = 0; r < repeats; ++r)
    for (const std::string& encoding : encodings) {
      const auto scene = csim::load_scene(
          scene_file, {"parameters.divisions=" + std::to_string(divisions), "time.step=0.01", "time.end=4",
                       "output.paraview=" + encoding});
      // A folder of its own for each run, all deleted at the end: on an ext4 without a journal (this
      // machine's), creating a file soon after others were deleted costs a scan of their inodes
      // (ext4's recently_deleted), which deleting the previous run's files would charge to this one.
      const fs::path dir = root / (encoding + std::to_string(r));
      const auto start = Clock::now();
      const double cpu_start = cpu_seconds();
      const csim::RunReport report = csim::run_scene(*scene, {dir.string()});
      seconds[encoding].push_back(std::chrono::duration<double>(Clock::now() - start).count());
      cpu[encoding].push_back(cpu_seconds() - cpu_start);
      bytes[encoding] = folder_bytes(dir / "paraview");
      frames = report.sample_times.size();
    }

  std::printf("SDNV104 shoe, %d x %d QUAD4, step 0.01 s to 4 s, %zu frames, into %s; %d runs each, alternating\n",
              divisions, divisions, frames, root.c_str(), repeats);
  std::printf("%-8s %10s %20s %14s %10s %14s %12s\n", "paraview", "median s", "min-max s", "output share", "CPU s",
              "CPU share", "MB written");
  const double none = median(seconds["none"]), none_cpu = median(cpu["none"]);
  for (const std::string& encoding : encodings) {
    const auto& v = seconds[encoding];
    const double m = median(v), c = median(cpu[encoding]);
    std::printf("%-8s %10.3f %9.3f - %-8.3f %13.0f%% %10.3f %13.0f%% %12.1f\n", encoding.c_str(), m,
                *std::min_element(v.begin(), v.end()), *std::max_element(v.begin(), v.end()),
                100.0 * (m - none) / m, c, 100.0 * (c - none_cpu) / c, bytes[encoding] / 1e6);
  }

  // zlib levels on the binary run's per-frame arrays (the mesh's four arrays are compressed once per run).
  std::vector<std::string> blocks;
  std::size_t input = 0;
  for (const auto& entry : fs::directory_iterator(root / "binary0" / "paraview")) {
    if (entry.path().filename().string().rfind("shoe_", 0) != 0) continue;
    std::vector<std::string> arrays = appended_arrays(entry.path());
    arrays.resize(arrays.size() - 4);  // points, connectivity, offsets, types
    for (const std::string& a : arrays)
      for (std::size_t at = 0; at < a.size(); at += 32768) {
        blocks.push_back(a.substr(at, 32768));
        input += blocks.back().size();
      }
  }
  fs::remove_all(root);
  std::printf("\nzlib on the per-frame arrays of %zu frames (%.1f MB), VTK's 32 KiB blocks; median of %d\n",
              frames, input / 1e6, repeats);
  std::printf("%-14s %12s %12s %10s\n", "level", "ms/frame", "MB out", "ratio");
  std::vector<unsigned char> out(compressBound(32768) + 64);
  const std::pair<int, int> settings[] = {{1, Z_DEFAULT_STRATEGY}, {2, Z_DEFAULT_STRATEGY}, {3, Z_DEFAULT_STRATEGY},
                                          {6, Z_DEFAULT_STRATEGY}, {9, Z_DEFAULT_STRATEGY}, {1, Z_RLE},
                                          {1, Z_HUFFMAN_ONLY}};
  for (const auto& [level, strategy] : settings) {
    std::vector<double> times;
    std::size_t output = 0;
    for (int r = 0; r < repeats; ++r) {
      output = 0;
      const auto start = Clock::now();
      for (const std::string& b : blocks) {  // one zlib stream per block, as compress2 writes it
        z_stream z{};
        deflateInit2(&z, level, Z_DEFLATED, 15, 8, strategy);
        z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(b.data()));
        z.avail_in = b.size();
        z.next_out = out.data();
        z.avail_out = out.size();
        deflate(&z, Z_FINISH);
        output += z.total_out;
        deflateEnd(&z);
      }
      times.push_back(std::chrono::duration<double>(Clock::now() - start).count());
    }
    const char* name = strategy == Z_RLE ? " rle" : strategy == Z_HUFFMAN_ONLY ? " huffman" : "";
    std::printf("%d%-13s %12.3f %12.1f %10.3f\n", level, name, 1e3 * median(times) / frames, output / 1e6,
                double(output) / input);
  }
  return 0;
}
