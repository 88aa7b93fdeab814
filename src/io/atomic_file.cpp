#include "cwe/io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <mutex>
#include <string>
#include <system_error>
#include <vector>

#include "cwe/core/assert.hpp"
#include "cwe/core/error.hpp"

namespace cwe {
namespace {

// The folders whose files are synced together (sync_together_under); writers on any thread read
// it at commit.
std::mutex together_mutex;
std::vector<std::filesystem::path> together;

bool synced_together(const std::filesystem::path& path) {
  const std::lock_guard lock(together_mutex);
  return std::any_of(together.begin(), together.end(), [&](const std::filesystem::path& folder) {
    const auto [end, _] = std::mismatch(folder.begin(), folder.end(), path.begin(), path.end());
    return end == folder.end();
  });
}

// fsync of the file or folder at `path`; InputError naming it when that fails.
void sync(const std::filesystem::path& path, bool is_folder) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | (is_folder ? O_DIRECTORY : 0));
  const bool synced = fd >= 0 && ::fsync(fd) == 0;
  const std::string why = std::strerror(errno);
  if (fd >= 0) ::close(fd);
  if (!synced) throw InputError(SourceLocation{path.string()}, "cannot write the file: " + why);
}

}  // namespace

void sync_together_under(const std::filesystem::path& folder) {
  const std::lock_guard lock(together_mutex);
  together.push_back(folder.lexically_normal());
}

void syncs_apart(const std::filesystem::path& folder) {
  const std::lock_guard lock(together_mutex);
  const auto at = std::find(together.begin(), together.end(), folder.lexically_normal());
  if (at != together.end()) together.erase(at);
}

void sync_file(const std::filesystem::path& path) { sync(path, false); }

void sync_folder(const std::filesystem::path& folder,
                 const std::vector<std::filesystem::path>& synced) {
  std::error_code ec;
  for (std::filesystem::recursive_directory_iterator it(folder, ec), end; !ec && it != end;
       it.increment(ec)) {
    const bool is_folder = it->is_directory(ec);
    if (std::find(synced.begin(), synced.end(), it->path()) != synced.end()) {
      if (is_folder) it.disable_recursion_pending();
      continue;
    }
    if (is_folder || it->is_regular_file(ec)) sync(it->path(), is_folder);
  }
  if (ec) {
    throw InputError(SourceLocation{folder.string()}, "cannot read the folder: " + ec.message());
  }
  sync(folder, true);
}

AtomicFileWriter::AtomicFileWriter(std::filesystem::path path) : path_(std::move(path)) {
  std::error_code ec;
  if (path_.has_parent_path()) {
    std::filesystem::create_directories(path_.parent_path(), ec);
    if (ec) fail(ec.message());
  }
  temporary_ = path_.string() + ".tmp-" + std::to_string(static_cast<long>(::getpid()));
  file_ = std::fopen(temporary_.c_str(), "wb");
  if (file_ == nullptr) fail(std::strerror(errno));
}

AtomicFileWriter::~AtomicFileWriter() {
  if (file_ == nullptr) return;
  std::fclose(file_);
  std::error_code ec;
  std::filesystem::remove(temporary_, ec);
}

void AtomicFileWriter::fail(const std::string& why) {
  if (file_ != nullptr) {
    std::fclose(file_);
    file_ = nullptr;
    std::error_code ec;
    std::filesystem::remove(temporary_, ec);
  }
  throw InputError(SourceLocation{path_.string()}, "cannot write the file: " + why);
}

void AtomicFileWriter::append(std::string_view text) {
  if (file_ == nullptr) fail("the file was already committed");
  if (std::fwrite(text.data(), 1, text.size(), file_) != text.size()) fail(std::strerror(errno));
  appended_ += text.size();
}

void AtomicFileWriter::overwrite(std::size_t offset, std::string_view bytes) {
  if (file_ == nullptr) fail("the file was already committed");
  CWE_ASSERT(offset <= appended_ && bytes.size() <= appended_ - offset,
             "overwriting bytes not yet appended");
  if (std::fflush(file_) != 0) fail(std::strerror(errno));
  const ssize_t wrote =
      ::pwrite(::fileno(file_), bytes.data(), bytes.size(), static_cast<off_t>(offset));
  if (wrote != static_cast<ssize_t>(bytes.size())) {
    fail(wrote < 0 ? std::strerror(errno) : "only part of it was written");
  }
}

void AtomicFileWriter::start_writeback() {
  if (file_ == nullptr) fail("the file was already committed");
  if (std::fflush(file_) != 0) fail(std::strerror(errno));
  if (appended_ == started_) return;
  ::sync_file_range(::fileno(file_), static_cast<off_t>(started_),
                    static_cast<off_t>(appended_ - started_), SYNC_FILE_RANGE_WRITE);
  started_ = appended_;
}

void AtomicFileWriter::commit() {
  if (file_ == nullptr) fail("the file was already committed");
  bool flushed = std::fflush(file_) == 0;
  if (flushed && !synced_together(path_.lexically_normal())) {
    flushed = ::fsync(::fileno(file_)) == 0;
  } else if (flushed) {
    // Write-back started now, waited for by sync_folder (a hint: its errors show there).
    ::sync_file_range(::fileno(file_), 0, 0, SYNC_FILE_RANGE_WRITE);
  }
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  std::error_code ec;
  if (!flushed || !closed) {
    const std::string why = std::strerror(errno);
    std::filesystem::remove(temporary_, ec);
    fail(why);
  }
  std::filesystem::rename(temporary_, path_, ec);
  if (ec) {
    const std::string why = ec.message();
    std::filesystem::remove(temporary_, ec);
    fail(why);
  }
}

void write_file_atomically(const std::filesystem::path& path, std::string_view content) {
  AtomicFileWriter writer(path);
  writer.append(content);
  writer.commit();
}

}  // namespace cwe
