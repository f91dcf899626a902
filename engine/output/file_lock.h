#pragma once
// An exclusive advisory lock on a file (flock), held for the object's
// lifetime: processes sharing a cache folder (the shards of a sweep) render
// a cached file once, the others waiting and then reading it.
#include <string>

namespace cr {

class FileLock {
 public:
  explicit FileLock(const std::string& path);  // creates the file; blocks until locked; Error on failure
  ~FileLock();
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace cr
