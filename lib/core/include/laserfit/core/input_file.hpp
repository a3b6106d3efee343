#pragma once
// The checks every reader makes before a parser sees a file, in one place. A path comes from the
// command line or from inside another file (a scene's mesh, a cell's scene, a manifest's list), so
// it may be hostile: too long for the OS, a loop of links, unreadable. std::filesystem throws for
// those; these functions answer with a laserfit::Error naming the (clipped) path instead.
#include <string>

namespace laserfit {

// The path as an error line shows it: whole up to 160 characters, else its start and its end.
std::string shown_path(const std::string& path);

// Throws Error("<path>: no such file" / "not a regular file" / "file is empty" / "cannot use the
// path: <reason>"); `role` names where the path was listed ("listed in the manifest"), or is empty.
enum class EmptyFile { refused, allowed };
void require_input_file(const std::string& path, const std::string& role = "",
                        EmptyFile empty = EmptyFile::refused);

// True when the path names an existing directory; false for anything else, errors included.
bool is_existing_directory(const std::string& path);

}  // namespace laserfit
