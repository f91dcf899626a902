#pragma once
// The temporary files of atomic writes (atomic_file.h): their names,
// NAME.tmp.PID.N, and the removal of those a killed process left behind.
#include <optional>
#include <string>
#include <string_view>
#include <sys/types.h>

namespace cr {

// A temporary path next to `path`, unique per process and call, so
// concurrent writers (threads or processes) of one target never share it.
std::string temp_path_for(const std::string& path);

// The PID in a file name of the form NAME.tmp.PID.N (NAME not empty, PID and
// N decimal digits); nullopt for any other name.
std::optional<pid_t> temp_file_writer(std::string_view file_name);

// Removes the regular files of `directory` named NAME.tmp.PID.N whose PID is
// no running process (kill(PID, 0) fails with ESRCH), i.e. what a process
// killed mid-write left. A live PID's files stay: another run may be writing
// into the same folder. Scans each directory at most once per process; best
// effort (a folder that cannot be read is left as it is).
void remove_dead_writers_temp_files(const std::string& directory);

}  // namespace cr
