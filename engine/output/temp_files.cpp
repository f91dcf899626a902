#include "engine/output/temp_files.h"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <charconv>
#include <filesystem>
#include <mutex>
#include <set>

namespace cr {
namespace {

bool all_digits(std::string_view s) {
  return !s.empty() && s.find_first_not_of("0123456789") == std::string_view::npos;
}

// ESRCH only: EPERM means a live process of another user.
bool process_is_dead(pid_t pid) { return ::kill(pid, 0) != 0 && errno == ESRCH; }

}  // namespace

std::string temp_path_for(const std::string& path) {
  static std::atomic<unsigned long> counter{0};
  return path + ".tmp." + std::to_string(static_cast<long>(::getpid())) + "." +
         std::to_string(counter.fetch_add(1));
}

std::optional<pid_t> temp_file_writer(std::string_view file_name) {
  const size_t counter_dot = file_name.rfind('.');
  if (counter_dot == std::string_view::npos || !all_digits(file_name.substr(counter_dot + 1))) return std::nullopt;
  const std::string_view head = file_name.substr(0, counter_dot);
  const size_t pid_dot = head.rfind('.');
  if (pid_dot == std::string_view::npos) return std::nullopt;
  const std::string_view digits = head.substr(pid_dot + 1);
  const std::string_view name_tmp = head.substr(0, pid_dot);
  constexpr std::string_view kTmp = ".tmp";
  if (!all_digits(digits) || name_tmp.size() <= kTmp.size() || !name_tmp.ends_with(kTmp)) return std::nullopt;
  pid_t pid = 0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), pid);
  // PID 0 would make kill() address our own process group.
  if (error != std::errc() || end != digits.data() + digits.size() || pid <= 0) return std::nullopt;
  return pid;
}

void remove_dead_writers_temp_files(const std::string& directory) {
  static std::mutex mutex;
  static std::set<std::string> scanned;
  std::error_code ec;
  const std::string key = std::filesystem::absolute(directory, ec).lexically_normal().string();
  if (ec) return;
  std::lock_guard<std::mutex> lock(mutex);
  if (scanned.count(key)) return;
  std::filesystem::directory_iterator it(directory, ec);
  if (ec) return;  // not made yet, or unreadable: the write itself reports that
  scanned.insert(key);
  for (; it != std::filesystem::directory_iterator(); it.increment(ec)) {
    if (ec) return;
    const std::optional<pid_t> writer = temp_file_writer(it->path().filename().string());
    if (!writer || !process_is_dead(*writer)) continue;
    std::error_code ignored;
    if (it->symlink_status(ignored).type() == std::filesystem::file_type::regular)
      std::filesystem::remove(it->path(), ignored);
  }
}

}  // namespace cr
