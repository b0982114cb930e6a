// Scene text -> JSON document, before any schema check: the byte prescan (UTF-8 validity, nesting
// depth) so hostile input never reaches the parser, then a SAX parse into a DOM that also reports
// duplicate object keys (nlohmann keeps the last one silently).
#pragma once

#include <string>
#include <vector>

#include "server/codec/decoder.h"

namespace lambert::codec {

struct ParsedDocument {
  json doc;                               // meaningful only when fatal is empty
  std::vector<DecodeError> fatal;         // the text is not JSON (at most one error)
  std::vector<DecodeError> duplicate_keys;  // the text is JSON, but keys repeat (the first ones)
  std::size_t omitted_duplicate_keys = 0;   // repeated keys beyond those listed
};

ParsedDocument parse_document(const std::string& text);

}  // namespace lambert::codec
