// Reads a .vtu as VTK's XML reader would, in any of the writer's encodings (vtk_data_array.h), and
// checks its structure on the way: the XML part through XmlReader; for appended data, the
// <AppendedData encoding="raw"> block opened by '_', each appended DataArray's offset at the end of the
// previous one and the last ending where the block does, VTK's compression header (block count, block
// size, partial last block, compressed sizes) and every block inflating to its stated size, a byte count
// that is a whole number of values of the array's type. The decoded values are put into each
// DataArray's text, so that XmlElement::numbers() reads every encoding alike; each array's length is
// checked against its tuple count (NumberOfPoints for PointData and Points, NumberOfCells for CellData,
// offsets and types) times NumberOfComponents. Throws std::runtime_error saying what is wrong.
#pragma once

#include "tests/tools/output/xml_reader.h"

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#ifdef CSIM_HAVE_ZLIB
#include <zlib.h>
#endif

namespace csim::test_vtu {

using test_xml::XmlElement;
using test_xml::XmlReader;

struct VtuFile {
  XmlElement root;                    // <VTKFile>
  std::vector<std::string> comments;  // before the root
  bool appended = false;              // had an <AppendedData> block
  bool compressed = false;            // compressor="vtkZLibDataCompressor"
};

namespace detail {

inline std::uint64_t word_at(const std::string& bytes, std::size_t at) {
  if (at + 8 > bytes.size()) throw std::runtime_error("appended data ends inside a header at " + std::to_string(at));
  std::uint64_t word;
  std::memcpy(&word, bytes.data() + at, 8);
  return word;
}

inline std::size_t word_size(const std::string& type) {
  if (type == "Float64" || type == "Int64" || type == "UInt64") return 8;
  if (type == "Int32" || type == "UInt32" || type == "Float32") return 4;
  if (type == "UInt8" || type == "Int8") return 1;
  throw std::runtime_error("unknown DataArray type " + type);
}

template <typename T>
void put_values(std::string& text, const std::string& bytes) {
  for (std::size_t i = 0; i < bytes.size(); i += sizeof(T)) {
    T value;
    std::memcpy(&value, bytes.data() + i, sizeof(T));
    char buffer[32];
    const auto end = std::to_chars(buffer, buffer + sizeof buffer, value).ptr;
    text.append(buffer, end);
    text += ' ';
  }
}

// The array's bytes from `at` in the appended block; `end` gets the offset after it.
inline std::string array_bytes(const std::string& block, std::size_t at, bool compressed, std::size_t& end) {
  if (!compressed) {
    const std::uint64_t size = word_at(block, at);
    if (at + 8 + size > block.size()) throw std::runtime_error("array at " + std::to_string(at) + " overruns the block");
    end = at + 8 + size;
    return block.substr(at + 8, size);
  }
  const std::uint64_t blocks = word_at(block, at), block_size = word_at(block, at + 8),
                      last_size = word_at(block, at + 16);
  if (block_size == 0 || last_size >= block_size) throw std::runtime_error("bad compression header");
  std::size_t position = at + 24 + 8 * blocks;
  std::string out;
#ifdef CSIM_HAVE_ZLIB
  for (std::uint64_t b = 0; b < blocks; ++b) {
    const std::uint64_t compressed_size = word_at(block, at + 24 + 8 * b);
    if (position + compressed_size > block.size()) throw std::runtime_error("compressed block overruns the data");
    const std::uint64_t expected = (b + 1 == blocks && last_size > 0) ? last_size : block_size;
    std::string inflated(expected, '\0');
    uLongf length = static_cast<uLongf>(expected);
    if (uncompress(reinterpret_cast<Bytef*>(inflated.data()), &length,
                   reinterpret_cast<const Bytef*>(block.data() + position), compressed_size) != Z_OK ||
        length != expected)
      throw std::runtime_error("a compressed block does not inflate to its stated size");
    out += inflated;
    position += compressed_size;
  }
#else
  if (blocks > 0) throw std::runtime_error("compressed data, and the tests were built without zlib");
#endif
  end = position;
  return out;
}

inline void collect_arrays(XmlElement& element, const std::string& section, std::vector<std::pair<XmlElement*, std::string>>& out) {
  for (XmlElement& child : element.children) {
    if (child.name == "DataArray") out.emplace_back(&child, section);
    else collect_arrays(child, child.name, out);
  }
}

}  // namespace detail

inline VtuFile read_vtu(const std::string& text) {
  VtuFile file;
  const std::string opening = "<AppendedData encoding=\"raw\">";
  const std::size_t appended_at = text.find(opening);
  std::string xml = text, block;
  if (appended_at != std::string::npos) {
    file.appended = true;
    const std::size_t underscore = text.find('_', appended_at + opening.size());
    if (underscore == std::string::npos) throw std::runtime_error("no '_' opens the appended data");
    for (std::size_t i = appended_at + opening.size(); i < underscore; ++i)
      if (!std::isspace(static_cast<unsigned char>(text[i]))) throw std::runtime_error("text before the '_'");
    const std::string closing = "\n  </AppendedData>\n</VTKFile>\n";
    if (text.size() < underscore + 1 + closing.size() || text.compare(text.size() - closing.size(), closing.size(), closing) != 0)
      throw std::runtime_error("the appended data is not closed by </AppendedData></VTKFile>");
    block = text.substr(underscore + 1, text.size() - closing.size() - underscore - 1);
    xml = text.substr(0, appended_at) + "</VTKFile>\n";
  }
  XmlReader reader(xml);
  file.root = reader.document();
  file.comments = reader.prolog_comments();
  const auto& attributes = file.root.attributes;
  if (attributes.count("byte_order") == 0 || attributes.at("byte_order") != "LittleEndian")
    throw std::runtime_error("byte_order is not LittleEndian");
  if (attributes.count("header_type") == 0 || attributes.at("header_type") != "UInt64")
    throw std::runtime_error("header_type is not UInt64");
  if (attributes.count("compressor")) {
    if (attributes.at("compressor") != "vtkZLibDataCompressor") throw std::runtime_error("unknown compressor");
    file.compressed = true;
  }

  std::vector<std::pair<XmlElement*, std::string>> arrays;
  detail::collect_arrays(file.root, "", arrays);
  std::vector<std::pair<std::size_t, XmlElement*>> by_offset;
  for (auto& [array, section] : arrays) {
    const std::string format = array->attributes.count("format") ? array->attributes.at("format") : "";
    if (format == "appended") {
      if (!file.appended) throw std::runtime_error("an appended DataArray and no <AppendedData>");
      by_offset.emplace_back(std::stoull(array->attributes.at("offset")), array);
    } else if (format != "ascii") {
      throw std::runtime_error("DataArray format '" + format + "'");
    }
  }
  std::sort(by_offset.begin(), by_offset.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::size_t expected_at = 0;
  for (const auto& [at, array] : by_offset) {
    if (at != expected_at) throw std::runtime_error("appended array at offset " + std::to_string(at) + ", expected " + std::to_string(expected_at));
    const std::string bytes = detail::array_bytes(block, at, file.compressed, expected_at);
    const std::string type = array->attributes.at("type");
    if (bytes.size() % detail::word_size(type) != 0) throw std::runtime_error("a partial value in " + type + " data");
    array->text.clear();
    if (type == "Float64") detail::put_values<double>(array->text, bytes);
    else if (type == "Int64") detail::put_values<std::int64_t>(array->text, bytes);
    else if (type == "Int32") detail::put_values<std::int32_t>(array->text, bytes);
    else if (type == "UInt8") detail::put_values<std::uint8_t>(array->text, bytes);
    else throw std::runtime_error("no decoder for " + type);
  }
  if (file.appended && expected_at != block.size())
    throw std::runtime_error("the appended data has " + std::to_string(block.size() - expected_at) + " bytes after its last array");

  // Array lengths against the piece's counts.
  const XmlElement& grid = file.root.child(file.root.attributes.at("type"));
  for (const XmlElement& piece : grid.children) {
    if (piece.name != "Piece") continue;
    const std::size_t points = std::stoull(piece.attributes.at("NumberOfPoints")),
                      cells = std::stoull(piece.attributes.at("NumberOfCells"));
    for (const XmlElement& part : piece.children)
      for (const XmlElement& array : part.children) {
        if (array.name != "DataArray") continue;
        const std::size_t components = std::stoull(array.attributes.at("NumberOfComponents"));
        const std::string name = array.attributes.count("Name") ? array.attributes.at("Name") : "";
        std::size_t tuples = 0;
        if (part.name == "PointData" || part.name == "Points") tuples = points;
        else if (part.name == "CellData" || name == "offsets" || name == "types") tuples = cells;
        else continue;  // connectivity: as long as the cells make it
        if (array.numbers().size() != tuples * components)
          throw std::runtime_error(part.name + " " + name + ": " + std::to_string(array.numbers().size()) +
                                   " values, expected " + std::to_string(tuples * components));
      }
  }
  return file;
}

}  // namespace csim::test_vtu
