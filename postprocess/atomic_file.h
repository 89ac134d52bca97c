#ifndef FREESTAND_POST_ATOMIC_FILE_H
#define FREESTAND_POST_ATOMIC_FILE_H

// Outputs appear whole or not at all: written to PATH.part, then renamed, so
// a failed or interrupted write never replaces a good file already on disk.

#include <string>

namespace freestand {

// Writes `content` to PATH.part and renames it to PATH. InputError naming
// the path on failure (PATH.part is removed, PATH untouched).
void write_file_atomically(const std::string& path, const std::string& content);

// Renames a finished PATH.part (or any temporary) to PATH; InputError on failure.
void publish_file(const std::string& temporary, const std::string& path);

}  // namespace freestand

#endif
