// A minimal XML reader for the tests of the ParaView files: builds the element tree and throws
// std::runtime_error (with the offset) on anything not well-formed: unbalanced or misnested tags,
// unquoted, unseparated or duplicate attributes, unknown entities, content after the root element.
// No DTD, CDATA or processing instructions other than the leading <?xml ...?>, and comments only
// before the root element (prolog_comments()): our writers emit no others.
#pragma once

#include <cctype>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace csim::test_xml {

struct XmlElement {
  std::string name;
  std::map<std::string, std::string> attributes;
  std::string text;
  std::vector<XmlElement> children;

  const XmlElement& child(const std::string& tag) const {
    for (const XmlElement& c : children)
      if (c.name == tag) return c;
    throw std::runtime_error("no <" + tag + "> in <" + name + ">");
  }
  const XmlElement& array(const std::string& array_name) const {  // a DataArray by its Name
    for (const XmlElement& c : children)
      if (c.name == "DataArray" && c.attributes.count("Name") && c.attributes.at("Name") == array_name) return c;
    throw std::runtime_error("no DataArray " + array_name + " in <" + name + ">");
  }
  std::vector<double> numbers() const {
    std::istringstream in(text);
    std::vector<double> out;
    for (double x; in >> x;) out.push_back(x);
    if (!in.eof()) throw std::runtime_error("not a number in <" + name + ">");
    return out;
  }
};

class XmlReader {
 public:
  explicit XmlReader(std::string text) : s_(std::move(text)) {}

  XmlElement document() {
    skip_space();
    if (s_.compare(i_, 5, "<?xml") == 0) {
      const std::size_t end = s_.find("?>", i_);
      if (end == std::string::npos) fail("unterminated XML declaration");
      i_ = end + 2;
    }
    skip_space();
    while (s_.compare(i_, 4, "<!--") == 0) {
      const std::size_t end = s_.find("--", i_ + 4);
      if (end == std::string::npos) fail("unterminated comment");
      if (s_.compare(end, 3, "-->") != 0) fail("'--' inside a comment");
      comments_.push_back(s_.substr(i_ + 4, end - i_ - 4));
      i_ = end + 3;
      skip_space();
    }
    XmlElement root = element();
    skip_space();
    if (i_ != s_.size()) fail("content after the root element");
    return root;
  }
  // The text of each comment before the root element, in order (read by document()).
  const std::vector<std::string>& prolog_comments() const { return comments_; }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(what + " at offset " + std::to_string(i_));
  }
  void skip_space() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  void expect(char c) {
    if (i_ >= s_.size() || s_[i_] != c) fail(std::string("expected '") + c + "'");
    ++i_;
  }
  std::string name() {
    const std::size_t start = i_;
    while (i_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[i_])) || s_[i_] == '_' || s_[i_] == '-' ||
                              s_[i_] == '.' || s_[i_] == ':'))
      ++i_;
    if (i_ == start || std::isdigit(static_cast<unsigned char>(s_[start]))) fail("expected a name");
    return s_.substr(start, i_ - start);
  }
  std::string character_data(char stop) {  // text up to `stop` or '<', entities checked
    const std::size_t start = i_;
    while (i_ < s_.size() && s_[i_] != stop && s_[i_] != '<') {
      if (s_[i_] == '&') {
        const std::size_t end = s_.find(';', i_);
        const std::string entity = end == std::string::npos ? "" : s_.substr(i_, end - i_ + 1);
        if (entity != "&amp;" && entity != "&lt;" && entity != "&gt;" && entity != "&quot;" && entity != "&apos;")
          fail("bad entity");
        i_ = end;
      }
      ++i_;
    }
    return s_.substr(start, i_ - start);
  }
  XmlElement element() {
    expect('<');
    XmlElement e;
    e.name = name();
    for (;;) {
      const bool spaced = i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]));
      skip_space();
      if (i_ >= s_.size()) fail("unterminated start tag");
      if (s_[i_] == '/' || s_[i_] == '>') break;
      if (!spaced) fail("attributes must be separated by spaces");
      const std::string key = name();
      skip_space();
      expect('=');
      skip_space();
      if (i_ >= s_.size() || (s_[i_] != '"' && s_[i_] != '\'')) fail("unquoted attribute " + key);
      const char quote = s_[i_++];
      const std::string value = character_data(quote);
      expect(quote);
      if (!e.attributes.emplace(key, value).second) fail("duplicate attribute " + key);
    }
    if (s_[i_] == '/') {
      ++i_;
      expect('>');
      return e;
    }
    expect('>');
    for (;;) {
      e.text += character_data('<');
      if (i_ >= s_.size()) fail("unclosed <" + e.name + ">");
      if (s_.compare(i_, 2, "</") == 0) break;
      e.children.push_back(element());
    }
    i_ += 2;
    if (name() != e.name) fail("</...> does not close <" + e.name + ">");
    skip_space();
    expect('>');
    return e;
  }

  std::string s_;
  std::size_t i_ = 0;
  std::vector<std::string> comments_;
};

}  // namespace csim::test_xml
