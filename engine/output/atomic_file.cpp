#include "engine/output/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "engine/core/error.h"
#include "engine/output/temp_files.h"

namespace cr {
namespace {

std::string errno_text(int error) { return std::strerror(error); }

std::string directory_of(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

// The first write into a folder also clears what killed runs left there.
std::string new_temp_path(const std::string& path) {
  remove_dead_writers_temp_files(directory_of(path));
  return temp_path_for(path);
}

void fsync_path(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    const int error = errno;
    throw Error(path + ": cannot open for sync: " + errno_text(error));
  }
  if (::fsync(fd) != 0) {
    const int error = errno;
    ::close(fd);
    throw Error(path + ": fsync failed: " + errno_text(error));
  }
  ::close(fd);
}

// Makes the rename itself durable. Best effort: some file systems refuse
// fsync on directories, and atomicity (what readers rely on) does not need it.
void sync_directory(const std::string& path) {
  const int fd = ::open(directory_of(path).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  (void)::fsync(fd);
  ::close(fd);
}

void rename_over(const std::string& temp, const std::string& path) {
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    const int error = errno;
    std::remove(temp.c_str());
    throw Error(path + ": cannot replace file: " + errno_text(error));
  }
  sync_directory(path);
}

}  // namespace

void write_file_atomic(const std::string& path, std::string_view bytes) {
  const std::string temp = new_temp_path(path);
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) {
    const int error = errno;
    throw Error(path + ": cannot create temporary file " + temp + ": " + errno_text(error));
  }
  auto fail = [&](const std::string& what, int error) {
    ::close(fd);
    std::remove(temp.c_str());
    throw Error(path + ": " + what + ": " + errno_text(error));
  };
  size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      fail("write failed", errno);
    }
    written += static_cast<size_t>(n);
  }
  if (::fsync(fd) != 0) fail("fsync failed", errno);
  if (::close(fd) != 0) {
    const int error = errno;
    std::remove(temp.c_str());
    throw Error(path + ": close failed: " + errno_text(error));
  }
  rename_over(temp, path);
}

void write_file_atomic(const std::string& path,
                       const std::function<void(const std::string& temp_path)>& write) {
  const std::string temp = new_temp_path(path);
  try {
    write(temp);
    fsync_path(temp);
  } catch (...) {
    std::remove(temp.c_str());
    throw;
  }
  rename_over(temp, path);
}

std::string read_file_bytes(const std::string& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    const int error = errno;
    throw InputError(path, "cannot read file: " + errno_text(error));
  }
  if (S_ISDIR(info.st_mode)) throw InputError(path, "is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int error = errno;
    throw InputError(path, "cannot open file: " + errno_text(error));
  }
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (in.bad()) throw InputError(path, "read error");
  return std::move(bytes).str();
}

}  // namespace cr
