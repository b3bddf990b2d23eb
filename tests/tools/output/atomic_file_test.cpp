// A file that cannot be written is reported with the system's reason (issue 53: a full disk said only
// "write failed"), and named in the folder the user asked for rather than in the temporary one.
// /dev/full answers every write with ENOSPC, as a full disk does: the writer's temporary file is made a
// link to it, the one way to fill a disk without root.
#include "tools/output/atomic_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <string>

namespace csim {
namespace {

namespace fs = std::filesystem;

class AtomicFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() / ("csim-atomic-file-test-" + std::to_string(getpid()));
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }
  fs::path folder_;
};

TEST_F(AtomicFileTest, AFullDiskSaysSoAndLeavesNothing) {
  if (!fs::exists("/dev/full")) GTEST_FAIL() << "/dev/full is missing: the full disk cannot be simulated";
  const std::string path = (folder_ / "contacts_000170.vtu").string();
  fs::create_symlink("/dev/full", path + ".tmp");  // where write_file_atomically writes first
  const std::string contents(1 << 20, 'x');          // more than any buffer: the writes reach the device
  try {
    write_file_atomically(path, contents);
    FAIL() << "a write to /dev/full succeeded";
  } catch (const FileWriteError& e) {
    EXPECT_EQ(e.code().value(), ENOSPC) << e.what();
    EXPECT_EQ(e.path, path);
    EXPECT_EQ(std::string(e.what()), path + ": cannot write: No space left on device");
  }
  EXPECT_FALSE(fs::exists(fs::symlink_status(path + ".tmp"))) << "the temporary file is left";
  EXPECT_FALSE(fs::exists(path));
  // The streamed form, a small text: the failure shows at the flush.
  fs::create_symlink("/dev/full", path + ".tmp");
  try {
    write_file_atomically(path, [](std::ostream& out) { out << "short"; });
    FAIL() << "a write to /dev/full succeeded";
  } catch (const FileWriteError& e) {
    EXPECT_EQ(e.code().value(), ENOSPC) << e.what();
  }
}

TEST_F(AtomicFileTest, AFolderThatCannotBeWrittenNamesTheReason) {
  const std::string path = (folder_ / "missing" / "summary.json").string();
  try {
    write_file_atomically(path, "{}");
    FAIL() << "written into a missing folder";
  } catch (const FileWriteError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": cannot open for writing: No such file or directory");
  }
}

TEST_F(AtomicFileTest, AFileIsWrittenWholeAndNamedInTheUsersFolder) {
  const std::string path = (folder_ / "probes.csv").string();
  write_file_atomically(path, "t,x\n0,1\n");
  std::ifstream in(path);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "t,x\n0,1\n");
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  // The temporary folder of a command, named as the folder the user asked for.
  const FileWriteError error("/abs/out/.pile.tmp-42/paraview/contacts_000170.vtu", "cannot write",
                             std::error_code(ENOSPC, std::generic_category()));
  const FileWriteError shown = error.in_folder("/abs/out/.pile.tmp-42", "out/pile");
  EXPECT_EQ(std::string(shown.what()), "out/pile/paraview/contacts_000170.vtu: cannot write: No space left on device");
  EXPECT_EQ(shown.code(), error.code());
  // Another folder, or one whose name only starts alike, is left as it is.
  EXPECT_EQ(error.in_folder("/abs/out/.pile.tmp-4", "out/pile").path, error.path);
  EXPECT_EQ(error.in_folder("/elsewhere", "out/pile").path, error.path);
}

}  // namespace
}  // namespace csim
