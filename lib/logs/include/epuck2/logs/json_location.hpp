// Where things are in a JSON text, for error messages that name file:line:column: the line and
// column of a byte offset, of the value at a JSON pointer, and of a number too large for a double.
// A small scanner of its own (no JSON library), run only when an error is being reported.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "epuck2/logs/log.hpp"

namespace epuck2::logs {

/// The 1-based line and character column of byte `offset` in `text` (LF, CRLF or a lone CR end a
/// line); an offset past the end gives the position just after the last character.
SourcePos position_of(std::string_view text, std::size_t offset);

/// Where the value at a JSON pointer (RFC 6901: "" the whole document, "/speeds/3/cubic") starts in
/// a JSON text; {0, 0} when the text does not hold it.
SourcePos locate_json_pointer(std::string_view text, std::string_view pointer);

/// The first number literal outside strings that overflows a double (e.g. 1e999); {0, 0} when none.
SourcePos locate_json_overflow(std::string_view text);

/// An InputError about the value at `pointer` in the JSON `text` read from `path`: at the value's
/// line and column, or at its nearest enclosing value that the text holds (a missing key names the
/// object it is missing from); the message ends with the JSON path.
InputError json_error(const std::string& path, std::string_view text, const std::string& pointer,
                      const std::string& message);

/// As json_error, for a document already parsed from the file `path`: reads the file again to find
/// the line (when it cannot, the error names the file and the JSON path only).
InputError json_file_error(const std::string& path, const std::string& pointer, const std::string& message);

}  // namespace epuck2::logs
