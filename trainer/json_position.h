// Where a key path ("script[3].t_s") sits in a JSON text: lets strict readers name the
// line of a bad value, not only its key (nlohmann::json keeps no positions).
#pragma once

#include <string>

namespace colosim {

/// Line (1-based) of the key path `path` in the JSON text: the line of the member's key
/// for object members, of the value for array elements. When the path does not exist
/// (a missing key), the line of its deepest existing ancestor; 0 when the text cannot be
/// scanned. Paths use "." between keys and "[i]" for array elements, as JsonObject does.
int lineOfKeyPath(const std::string& text, const std::string& path);

/// Rewrites an error message "FILE: PATH: message" (JsonObject's form) into
/// "FILE:LINE: PATH: message" using lineOfKeyPath; returns it unchanged when the form
/// or the path is not recognised.
std::string addLineToMessage(const std::string& message, const std::string& file,
                             const std::string& text);

}  // namespace colosim
