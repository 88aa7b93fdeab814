#pragma once
// Outputs are written whole or not at all: the content goes to a temporary file beside the
// target, is flushed, and is renamed over the target only when complete.

#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <string_view>
#include <vector>

namespace cwe {

// Writes `content` to `path` atomically (rename within the directory). Creates missing parent
// directories. Throws cwe::InputError naming the path when the file cannot be written; the
// target is then untouched.
void write_file_atomically(const std::filesystem::path& path, std::string_view content);

// Files committed under `folder` (and its subfolders) from now on are made durable by
// sync_folder(folder), not one by one; until syncs_apart(folder).
void sync_together_under(const std::filesystem::path& folder);
void syncs_apart(const std::filesystem::path& folder);
// Makes every file and folder under `folder`, and `folder` itself, durable (fsync), but those in
// `synced` (already durable; a folder there with all it holds). Throws InputError naming the
// first that cannot be synced.
void sync_folder(const std::filesystem::path& folder,
                 const std::vector<std::filesystem::path>& synced = {});
// Makes the file at `path` durable (fsync); throws InputError naming it when it cannot.
void sync_file(const std::filesystem::path& path);

// The same for content produced piece by piece (outputs too large to hold in memory): append()
// writes to the temporary file, commit() flushes it and renames it over the target. A writer
// destroyed without commit() (an error on the way) removes its temporary file and leaves the
// target untouched.
//
// commit() makes the file durable (fsync) before the rename, except under a folder whose files
// are synced together (sync_together_under, an OutputSet's staging folder): there it only starts
// the file's write-back, and sync_folder() waits for all of them before the folder is published.
// One by one, the syncs blocked the main job's threads for up to 80 ms a map figure, and its end
// for a fifth of a second on a 43 MB stock.stl.
class AtomicFileWriter {
 public:
  explicit AtomicFileWriter(std::filesystem::path path);
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;
  ~AtomicFileWriter();

  void append(std::string_view text);
  // Overwrites bytes already appended, from `offset` on (a count known only at the end).
  void overwrite(std::size_t offset, std::string_view bytes);
  // Hands what was appended to the system and starts the write-back (a hint) of what was appended
  // since the last call, so that a large file's durability costs less wait when commit() or
  // sync_folder() comes. Called every few megabytes while a large file is written, it keeps the
  // disk busy meanwhile.
  void start_writeback();
  // Bytes appended since the write-back was last started (all of them before the first start).
  std::size_t writeback_pending() const { return appended_ - started_; }
  void commit();
  const std::filesystem::path& path() const { return path_; }

 private:
  [[noreturn]] void fail(const std::string& why);

  std::filesystem::path path_;
  std::filesystem::path temporary_;
  std::FILE* file_ = nullptr;
  std::size_t appended_ = 0;  // bytes appended
  std::size_t started_ = 0;   // bytes whose write-back was started
};

}  // namespace cwe
