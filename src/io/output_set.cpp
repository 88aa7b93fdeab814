#include "cwe/io/output_set.hpp"

#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <string_view>
#include <system_error>

#include <fmt/format.h>

#include "cwe/core/error.hpp"
#include "cwe/io/atomic_file.hpp"

namespace cwe {
namespace {

constexpr std::string_view kStaging = ".cwe-staging-";
constexpr std::string_view kOld = ".cwe-old-";

// The pid at the end of a staging or old folder's name; 0 when there is none.
long pid_of(const std::string& name, std::string_view marker) {
  const std::size_t at = name.rfind(marker);
  if (at == std::string::npos) return 0;
  long pid = 0;
  for (std::size_t i = at + marker.size(); i < name.size(); ++i) {
    if (name[i] < '0' || name[i] > '9' || pid > 1'000'000'000) return 0;
    pid = pid * 10 + (name[i] - '0');
  }
  return pid;
}

bool running(long pid) {
  return pid > 0 && (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM);
}

}  // namespace

OutputSet::OutputSet(const std::filesystem::path& folder, std::vector<std::string> names,
                     SourceLocation option)
    : option_(std::move(option)) {
  std::error_code ec;
  folder_ = std::filesystem::absolute(folder, ec).lexically_normal();
  if (folder_.has_filename() == false) folder_ = folder_.parent_path();  // "out/" → "out"
  const auto fail = [&](const std::string& message) { throw InputError(option_, message); };
  const std::filesystem::path parent = folder_.parent_path();
  const std::string base = folder_.filename().string();
  if (base.empty() || folder_ == parent) {
    fail(
        fmt::format("'{}': expected a folder of its own for the outputs, which are replaced "
                    "as a whole",
                    folder.string()));
  }
  // The folder is renamed and deleted: never the working folder or one holding it.
  const std::filesystem::path here = std::filesystem::current_path(ec);
  const std::filesystem::path resolved = std::filesystem::weakly_canonical(folder_, ec);
  const auto [end, _] = std::mismatch(resolved.begin(), resolved.end(), here.begin(), here.end());
  if (!here.empty() && end == resolved.end()) {
    fail(
        fmt::format("'{}' is the working folder or holds it: the output folder is replaced as a "
                    "whole, so give one of its own (e.g. out)",
                    folder.string()));
  }
  std::filesystem::create_directories(parent, ec);
  if (ec) fail(fmt::format("cannot create {}: {}", parent.string(), ec.message()));

  // What earlier runs that were stopped left beside the folder: their staging folders go; an old
  // set renamed aside goes back when the folder is missing (a stop between the two renames).
  const std::string prefix = "." + base;
  for (const auto& entry : std::filesystem::directory_iterator(parent, ec)) {
    const std::string name = entry.path().filename().string();
    if (!name.starts_with(prefix)) continue;
    const std::string_view rest = std::string_view(name).substr(prefix.size());
    for (const std::string_view marker : {kStaging, kOld}) {
      if (!rest.starts_with(marker)) continue;
      const long pid = pid_of(name, marker);
      if (pid == 0 || running(pid)) continue;
      std::error_code ignored;
      if (marker == kOld && !std::filesystem::exists(folder_, ignored)) {
        std::filesystem::rename(entry.path(), folder_, ignored);
      } else {
        std::filesystem::remove_all(entry.path(), ignored);
      }
    }
  }

  if (std::filesystem::exists(folder_, ec)) {
    if (!std::filesystem::is_directory(folder_, ec)) {
      fail(fmt::format("{} is a file: expected a folder for the outputs", folder_.string()));
    }
    for (const auto& entry : std::filesystem::directory_iterator(folder_, ec)) {
      const std::string name = entry.path().filename().string();
      const bool ours = std::find(names.begin(), names.end(), name) != names.end() ||
                        name.find(".tmp-") != std::string::npos ||
                        name.starts_with(".cwe-write-test-");
      if (!ours) {
        fail(
            fmt::format("{} holds {}, which is not an output of this command: the folder is "
                        "replaced as a whole, so give a new or empty folder",
                        folder_.string(), name));
      }
    }
  }
  staging_ = parent / fmt::format("{}{}{}", prefix, kStaging, static_cast<long>(::getpid()));
  std::filesystem::remove_all(staging_, ec);
  if (!std::filesystem::create_directory(staging_, ec) || ec) {
    fail(fmt::format("cannot write beside {} (in {}): {}", folder_.string(), parent.string(),
                     ec ? ec.message() : std::string("it exists")));
  }
  // The folder must take files too, not only its parent.
  const std::filesystem::path probe = staging_ / ".cwe-write-test";
  if (!std::ofstream(probe).good()) {
    std::filesystem::remove_all(staging_, ec);
    fail(fmt::format("cannot write in {}: check the folder and its permissions", parent.string()));
  }
  std::filesystem::remove(probe, ec);
  sync_together_under(staging_);
}

OutputSet::~OutputSet() {
  ahead_.clear();  // waits for the syncs ahead (their errors matter only to publish())
  syncs_apart(staging_);
  if (published_) return;
  std::error_code ec;
  std::filesystem::remove_all(staging_, ec);
}

void OutputSet::sync_ahead(const std::vector<std::filesystem::path>& paths) {
  const auto sync = [](const std::vector<std::filesystem::path>& each) {
    for (const std::filesystem::path& path : each) {
      if (std::filesystem::is_directory(path)) {
        sync_folder(path);
      } else {
        sync_file(path);
      }
    }
  };
  std::future<void> started;
  try {
    started = std::async(std::launch::async, [sync, paths] { sync(paths); });
  } catch (const std::system_error&) {
    sync(paths);  // no thread to be had
  }
  const std::lock_guard lock(ahead_mutex_);
  if (started.valid()) ahead_.push_back(std::move(started));
  synced_ahead_.insert(synced_ahead_.end(), paths.begin(), paths.end());
}

void OutputSet::publish() {
  std::error_code ec;
  const auto fail = [&](const std::string& why) {
    throw InputError(SourceLocation{folder_.string()}, "cannot publish the outputs: " + why);
  };
  {
    const std::lock_guard lock(ahead_mutex_);
    for (std::future<void>& sync : ahead_) sync.get();
    ahead_.clear();
  }
  // Every staged file durable before the swap: their commits only started the write-back.
  sync_folder(staging_, synced_ahead_);
  if (!std::filesystem::exists(folder_, ec)) {
    if (::rename(staging_.c_str(), folder_.c_str()) != 0) fail(std::strerror(errno));
    published_ = true;
    return;
  }
  if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, folder_.c_str(), RENAME_EXCHANGE) == 0) {
    published_ = true;  // the old set is now at staging_
    std::filesystem::remove_all(staging_, ec);
    return;
  }
  if (errno != EINVAL && errno != ENOSYS && errno != ENOTSUP) fail(std::strerror(errno));
  // No exchange on this file system: the old set goes aside for the instant between two renames.
  const std::filesystem::path old =
      folder_.parent_path() /
      fmt::format(".{}{}{}", folder_.filename().string(), kOld, static_cast<long>(::getpid()));
  if (::rename(folder_.c_str(), old.c_str()) != 0) fail(std::strerror(errno));
  if (::rename(staging_.c_str(), folder_.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    ::rename(old.c_str(), folder_.c_str());
    fail(why);
  }
  published_ = true;
  std::filesystem::remove_all(old, ec);
}

}  // namespace cwe
