#include "geometry/xml_tree.h"

#include "core/error.h"

#include <expat.h>

#include <algorithm>
#include <exception>
#include <limits>

namespace hipfai::geometry {
namespace {

// State shared with expat's C callbacks. Exceptions must not unwind through expat's C frames:
// a callback that fails records the exception and stops the parser, parse_xml rethrows it.
struct Builder {
  XML_Parser parser = nullptr;
  const std::function<void(const XmlElement&)>* on_start = nullptr;
  std::unique_ptr<XmlElement> root;
  std::vector<XmlElement*> open;  // the element being filled is open.back()
  std::exception_ptr failure;

  void fail() {
    failure = std::current_exception();
    XML_StopParser(parser, XML_FALSE);
  }
};

void XMLCALL start_element(void* data, const XML_Char* name, const XML_Char** attributes) {
  auto& builder = *static_cast<Builder*>(data);
  try {
    auto element = std::make_unique<XmlElement>();
    element->name = name;
    for (const XML_Char** a = attributes; a[0] != nullptr; a += 2) element->attributes[a[0]] = a[1];
    XmlElement* raw = element.get();
    if (builder.open.empty()) {
      builder.root = std::move(element);
    } else {
      builder.open.back()->children.push_back(std::move(element));
    }
    builder.open.push_back(raw);
    if (*builder.on_start) (*builder.on_start)(*raw);
  } catch (...) {
    builder.fail();
  }
}

void XMLCALL end_element(void* data, const XML_Char* /*name*/) {
  auto& builder = *static_cast<Builder*>(data);
  if (!builder.open.empty()) builder.open.pop_back();  // expat has matched the names already
}

void XMLCALL character_data(void* data, const XML_Char* text, int length) {
  auto& builder = *static_cast<Builder*>(data);
  if (builder.open.empty() || length <= 0) return;
  try {
    builder.open.back()->text.append(text, static_cast<std::size_t>(length));
  } catch (...) {
    builder.fail();
  }
}

}  // namespace

std::string XmlElement::attribute(const std::string& key, const std::string& fallback) const {
  const auto it = attributes.find(key);
  return it == attributes.end() ? fallback : it->second;
}

std::unique_ptr<XmlElement> parse_xml(const std::string& name, std::string_view xml,
                                      const std::function<void(const XmlElement&)>& on_start) {
  std::unique_ptr<XML_ParserStruct, void (*)(XML_Parser)> parser(XML_ParserCreate(nullptr), &XML_ParserFree);
  if (!parser) throw_error(name, ": out of memory for the XML parser");
  Builder builder;
  builder.parser = parser.get();
  builder.on_start = &on_start;
  XML_SetUserData(parser.get(), &builder);
  XML_SetElementHandler(parser.get(), &start_element, &end_element);
  XML_SetCharacterDataHandler(parser.get(), &character_data);

  // XML_Parse takes an int length: larger documents go in chunks.
  constexpr std::size_t kChunk = std::size_t{1} << 30;
  std::size_t offset = 0;
  for (;;) {
    const std::size_t length = std::min(kChunk, xml.size() - offset);
    const bool last = offset + length == xml.size();
    const XML_Status status =
        XML_Parse(parser.get(), xml.data() + offset, static_cast<int>(length), last ? XML_TRUE : XML_FALSE);
    if (builder.failure) std::rethrow_exception(builder.failure);
    if (status != XML_STATUS_OK) {
      throw_error(name, ": malformed XML at line ", XML_GetCurrentLineNumber(parser.get()), ", column ",
                  XML_GetCurrentColumnNumber(parser.get()) + 1, ": ",
                  XML_ErrorString(XML_GetErrorCode(parser.get())));
    }
    offset += length;
    if (last) break;
  }
  if (!builder.root) throw_error(name, ": no XML element");
  return std::move(builder.root);
}

}  // namespace hipfai::geometry
