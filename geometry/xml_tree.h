// hipfai — an XML document as a tree of elements, parsed by expat (Debian's libexpat).
//
// For the XML mesh formats (VTP): a well-kept parser checks well-formedness, entities and
// encodings, so a broken file becomes one line "<name>: malformed XML at line L, column C:
// <expat's reason>" instead of a guess. Expat loads no external entities and (2.4+) limits
// entity expansion, so a hostile file cannot make it fetch or balloon.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace hipfai::geometry {

struct XmlElement {
  std::string name;
  std::map<std::string, std::string> attributes;  // entities already replaced
  std::string text;                               // character data directly inside, concatenated
  std::vector<std::unique_ptr<XmlElement>> children;

  // The attribute's value, or `fallback` when absent.
  std::string attribute(const std::string& key, const std::string& fallback = "") const;
};

// Parses `xml`. `on_start`, when given, sees every element as soon as its start tag is read
// (attributes set, no text or children yet) and may throw to stop there: a reader can reject
// what follows (e.g. raw binary data, which is not XML) with its own message. Throws
// hipfai::Error "<name>: malformed XML at line L, column C: <reason>" on a document that is not
// well-formed, and "<name>: no XML element" on one without a root.
std::unique_ptr<XmlElement> parse_xml(const std::string& name, std::string_view xml,
                                      const std::function<void(const XmlElement&)>& on_start = {});

}  // namespace hipfai::geometry
