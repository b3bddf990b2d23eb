#include "tools/output/vtk_data_array.h"

#include <bit>
#include <charconv>
#include <cstring>
#include <ostream>
#include <stdexcept>
#include <string_view>
#include <utility>

#ifdef CSIM_HAVE_ZLIB
#include <zlib.h>
#endif

namespace csim {

// The appended encodings copy the machine's bytes: the files say byte_order="LittleEndian".
static_assert(std::endian::native == std::endian::little, "the ParaView writer assumes a little-endian machine");

namespace {

// VTK's block size (vtkXMLWriter::BlockSize): a reader decompresses one block at a time.
constexpr std::size_t kBlockSize = 32768;
// zlib level 1, the fastest: the higher levels make these arrays (doubles) at most 2 % smaller for
// 1.1 to 14 times the time (docs/output.md).
constexpr int kCompressionLevel = 1;

// Beside the header's put_number(double): ascii_values finds both overloads here (this one alone would
// hide it, and the doubles would be written as integers).
using csim::put_number;

void put_number(std::string& out, std::int64_t value) {
  char buffer[24];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

void put_word(std::string& out, std::uint64_t word) {  // a header word, header_type="UInt64"
  char bytes[8];
  std::memcpy(bytes, &word, 8);
  out.append(bytes, 8);
}

// The appended block of `size` bytes at `bytes`: uncompressed, its length then the bytes; compressed,
// VTK's block header then the blocks.
std::string appended_block(const void* bytes, std::size_t size, bool compress) {
  std::string out;
  if (!compress) {
    out.reserve(8 + size);
    put_word(out, size);
    out.append(static_cast<const char*>(bytes), size);
    return out;
  }
#ifdef CSIM_HAVE_ZLIB
  const std::size_t blocks = (size + kBlockSize - 1) / kBlockSize;
  const std::size_t header = 8 * (3 + blocks);
  out.resize(header + blocks * compressBound(kBlockSize));
  std::vector<std::uint64_t> words{blocks, kBlockSize, size % kBlockSize};
  std::size_t end = header;
  for (std::size_t b = 0; b < blocks; ++b) {
    const std::size_t start = b * kBlockSize, length = std::min(kBlockSize, size - start);
    uLongf compressed = static_cast<uLongf>(out.size() - end);
    const int status = compress2(reinterpret_cast<Bytef*>(out.data() + end), &compressed,
                                 static_cast<const Bytef*>(bytes) + start, static_cast<uLong>(length),
                                 kCompressionLevel);
    if (status != Z_OK) throw std::runtime_error("zlib compress2 failed (" + std::to_string(status) + ")");
    words.push_back(compressed);
    end += compressed;
  }
  out.resize(end);
  for (std::size_t i = 0; i < words.size(); ++i) std::memcpy(out.data() + 8 * i, &words[i], 8);
  return out;
#else
  throw std::logic_error("zlib-compressed ParaView files: this csim was built without zlib");
#endif
}

std::string attributes(const char* type, const std::string& name, int components,
                       const std::vector<std::string>& component_names) {
  std::string out = "type=\"" + std::string(type) + "\"";
  if (!name.empty()) out += " Name=\"" + name + "\"";
  out += " NumberOfComponents=\"" + std::to_string(components) + "\"";
  for (std::size_t c = 0; c < component_names.size(); ++c)
    out += " ComponentName" + std::to_string(c) + "=\"" + component_names[c] + "\"";
  return out;
}

// One tuple per line, indented to sit inside its DataArray.
template <typename T>
std::string ascii_values(const std::vector<T>& values, int components) {
  std::string out;
  out.reserve(values.size() * 12);
  for (std::size_t i = 0; i < values.size(); ++i) {
    out += (i % components == 0) ? "          " : " ";
    put_number(out, values[i]);
    if ((i + 1) % components == 0) out += '\n';
  }
  return out;
}

// Integers stored as the width of their VTK type.
template <typename Stored>
std::string integer_block(const std::vector<std::int64_t>& values, bool compress) {
  std::vector<Stored> stored(values.begin(), values.end());
  return appended_block(stored.data(), stored.size() * sizeof(Stored), compress);
}

}  // namespace

bool vtk_compression_available() {
#ifdef CSIM_HAVE_ZLIB
  return true;
#else
  return false;
#endif
}

EncodedArray encode_array(VtkEncoding encoding, const char* type, const std::string& name, int components,
                          const std::vector<double>& values, const std::vector<std::string>& component_names) {
  if (std::string(type) != "Float64") throw std::logic_error("encode_array: doubles are written as Float64");
  EncodedArray out{attributes(type, name, components, component_names), {}, values.size()};
  if (encoding == VtkEncoding::ascii) out.data = ascii_values(values, components);
  else out.data = appended_block(values.data(), values.size() * sizeof(double), encoding == VtkEncoding::zlib);
  return out;
}

EncodedArray encode_array(VtkEncoding encoding, const char* type, const std::string& name, int components,
                          const std::vector<std::int64_t>& values, const std::vector<std::string>& component_names) {
  EncodedArray out{attributes(type, name, components, component_names), {}, values.size()};
  const bool compress = encoding == VtkEncoding::zlib;
  const std::string t = type;
  if (encoding == VtkEncoding::ascii) out.data = ascii_values(values, components);
  else if (t == "Int64") out.data = integer_block<std::int64_t>(values, compress);
  else if (t == "Int32") out.data = integer_block<std::int32_t>(values, compress);
  else if (t == "UInt8") out.data = integer_block<std::uint8_t>(values, compress);
  else throw std::logic_error("encode_array: unsupported integer type " + t);
  return out;
}

void put_number(std::string& out, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

void VtkFileText::open_dataset(const std::string& type, const std::string& prolog, double t,
                               const std::string& field_data) {
  open(type, prolog);
  xml_ += "  <" + type + ">\n    <FieldData>\n"
          "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">";
  put_number(xml_, t);
  xml_ += "</DataArray>\n" + field_data + "    </FieldData>\n";
}

void VtkFileText::open(const std::string& type, const std::string& prolog) {
  xml_ = "<?xml version=\"1.0\"?>\n" + prolog + "<VTKFile type=\"" + type +
         "\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\"";
  if (encoding_ == VtkEncoding::zlib) xml_ += " compressor=\"vtkZLibDataCompressor\"";
  xml_ += ">\n";
}

template <typename A>
void VtkFileText::put(A&& array, const char* indent) {
  xml_ += indent;
  xml_ += "<DataArray " + array.attributes;
  if (encoding_ == VtkEncoding::ascii) {
    xml_ += " format=\"ascii\">\n" + array.data + indent + "</DataArray>\n";
    return;
  }
  xml_ += " format=\"appended\" offset=\"" + std::to_string(appended_size_) + "\"/>\n";
  appended_size_ += array.data.size();
  appended_.push_back(&keep(std::forward<A>(array)));
}

void VtkFileText::array(const EncodedArray& array, const char* indent) { put(array, indent); }
void VtkFileText::array(EncodedArray&& array, const char* indent) { put(std::move(array), indent); }

template <typename Sink>
void VtkFileText::emit(Sink&& sink) const {
  sink(xml_);
  if (encoding_ == VtkEncoding::ascii) {
    sink("</VTKFile>\n");
    return;
  }
  sink("  <AppendedData encoding=\"raw\">\n   _");
  for (const std::string* data : appended_) sink(*data);
  sink("\n  </AppendedData>\n</VTKFile>\n");
}

std::string VtkFileText::finish() const {
  std::string out;
  out.reserve(xml_.size() + appended_size_ + 64);
  emit([&out](std::string_view piece) { out += piece; });
  return out;
}

void VtkFileText::write(std::ostream& out) const {
  emit([&out](std::string_view piece) { out.write(piece.data(), static_cast<std::streamsize>(piece.size())); });
}

}  // namespace csim
