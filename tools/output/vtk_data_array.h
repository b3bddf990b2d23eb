// The DataArrays of a VTK XML file (.vtu, .vtp) in one of the three encodings of output.paraview
// (docs/contract.md):
//
//   ascii    inline text, format="ascii": each value in its shortest form that reads back as the same
//            double;
//   binary   format="appended": the values as little-endian bytes in the file's one
//            <AppendedData encoding="raw"> block, uncompressed: the fastest to write;
//   zlib     the same, each array zlib-compressed (vtkZLibDataCompressor, level 1): about half the
//            size of binary, at several times its cost to write (docs/output.md). Only in a csim
//            built with zlib (vtk_compression_available()).
//
// VTK's layout of an appended array (vtkXMLWriter, header_type="UInt64"): uncompressed, the byte count
// then the bytes; compressed, the header [number of blocks, block size, size of a partial last block
// (0 when the last is full), compressed size of each block] then the blocks, each the zlib stream
// (compress2) of at most 32 KiB of the array's bytes. The offset="" of a DataArray counts from the byte
// after the '_' that opens the appended data.
//
// A file is assembled by VtkFileText: arrays are encoded apart (EncodedArray) so that a series can keep
// those that no frame changes (a mesh's points and cells) and compress them once.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <iosfwd>
#include <string>
#include <vector>

namespace csim {

enum class VtkEncoding { ascii, binary, zlib };

// True when this csim can write VtkEncoding::zlib (it was built with zlib).
bool vtk_compression_available();

// One encoded DataArray: its attributes without format/offset, and its data as the encoding stores it
// (the text for ascii; header and bytes for the appended encodings).
struct EncodedArray {
  std::string attributes;  // type="Float64" Name="..." NumberOfComponents="3" ComponentName0="..."
  std::string data;
  std::size_t values = 0;  // number of values (tuples × components)
};

// `values` of VTK type `type` ("Float64", "Int64", "Int32", "UInt8"), `components` per tuple; an empty
// name gives no Name attribute (a Points array). Component names show in ParaView's array selector.
EncodedArray encode_array(VtkEncoding encoding, const char* type, const std::string& name, int components,
                          const std::vector<double>& values, const std::vector<std::string>& component_names = {});
EncodedArray encode_array(VtkEncoding encoding, const char* type, const std::string& name, int components,
                          const std::vector<std::int64_t>& values,
                          const std::vector<std::string>& component_names = {});

// The shortest text that reads back as the same double (a TimeValue, a .pvd's timestep, an ascii value).
void put_number(std::string& out, double value);

// The text of one VTK XML file. open() writes the root element; array() a DataArray (inline, or a
// reference into the appended data); finish() the appended data and the closing of the root, as one
// string, or write() the same bytes to a stream without assembling them: a large frame's arrays are
// then held once, not twice (the file of a 52k-DOF body is about 9 MB).
class VtkFileText {
 public:
  explicit VtkFileText(VtkEncoding encoding) : encoding_(encoding) {}
  VtkFileText(const VtkFileText&) = delete;  // appended_ points into owned_
  VtkFileText& operator=(const VtkFileText&) = delete;
  // The XML declaration, `prolog` (comment lines), and <VTKFile type="TYPE" ...>.
  void open(const std::string& type, const std::string& prolog);
  // open(), then the dataset element <TYPE> and its FieldData: the time t (s) as TimeValue, always as
  // text (ParaView reads it when one file is opened without its .pvd), then `field_data` (whole
  // DataArray elements). The caller writes the <Piece> that follows.
  void open_dataset(const std::string& type, const std::string& prolog, double t, const std::string& field_data = "");
  std::string& xml() { return xml_; }  // for the elements between the arrays
  // An array the caller keeps until finish() (a series' mesh), or one handed over: its data is copied
  // once, into the file's text.
  void array(const EncodedArray& array, const char* indent = "        ");
  void array(EncodedArray&& array, const char* indent = "        ");
  std::string finish() const;
  void write(std::ostream& out) const;

 private:
  template <typename Sink>
  void emit(Sink&& sink) const;  // the file's text, piece by piece, to sink(std::string_view)
  const std::string& keep(const EncodedArray& array) { return array.data; }
  const std::string& keep(EncodedArray&& array) { return owned_.emplace_back(std::move(array.data)); }
  template <typename A>
  void put(A&& array, const char* indent);

  VtkEncoding encoding_;
  std::string xml_;
  std::deque<std::string> owned_;              // the data of the arrays handed over
  std::vector<const std::string*> appended_;   // the appended data, in order
  std::size_t appended_size_ = 0;              // bytes
};

}  // namespace csim
