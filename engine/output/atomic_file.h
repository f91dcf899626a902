#pragma once
// Atomic file output: data goes to a temporary file in the target's directory,
// is flushed to disk, then renamed over the target. A reader (or a golden
// test) therefore sees either the old file or the complete new one, never a
// half-written file, even if the process dies mid-write. What such a death
// leaves (NAME.tmp.PID.N) is removed by the next process's first write into
// that folder (temp_files.h).
#include <functional>
#include <string>
#include <string_view>

namespace cr {

// Writes `bytes` to `path` atomically. Throws cr::Error naming the path and
// the system error; on failure the target is untouched and no temp file remains.
void write_file_atomic(const std::string& path, std::string_view bytes);

// For libraries that write to a path themselves (OpenEXR): `write` receives a
// temporary path in the target's directory and must create the complete file
// there. It is then synced and renamed over `path`. If `write` throws, the
// temporary file is removed and the exception propagates unchanged.
void write_file_atomic(const std::string& path,
                       const std::function<void(const std::string& temp_path)>& write);

// Reads a whole file. Throws cr::InputError naming the path when it cannot be read.
std::string read_file_bytes(const std::string& path);

}  // namespace cr
