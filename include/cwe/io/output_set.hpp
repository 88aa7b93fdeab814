#pragma once
// A command's output folder, replaced whole or not at all.
//
// The outputs are written into a staging folder beside the output folder
// (`.<name>.cwe-staging-<pid>`); publish() makes them durable (sync_folder: the files written
// there are synced together, not one by one, see atomic_file.hpp), then swaps the two in one
// atomic step (renameat2 RENAME_EXCHANGE; a plain rename when there was no folder yet) and
// removes the old set. A run stopped at any point — an error, Ctrl-C, kill -9, a power cut after
// the swap — leaves either the previous set untouched or the new set complete, plus at most a
// staging folder, which the next run into the same folder removes. On a file system that cannot
// exchange two names, the old folder is renamed aside for the instant between two renames
// (`.<name>.cwe-old-<pid>`; the next run puts it back if the new one is not there).
//
// cwe owns the folder: it must be new, empty, or hold only the outputs the command writes
// (anything else would be deleted with the old set, so it is refused).

#include <filesystem>
#include <future>
#include <mutex>
#include <string>
#include <vector>

#include "cwe/core/error.hpp"

namespace cwe {

class OutputSet {
 public:
  // Removes what runs into `folder` that are gone left behind, checks that the folder holds
  // nothing but `names` (the command's outputs; "*.tmp-*" temporaries too) and that its parent
  // takes a new folder, and creates the staging folder. Throws InputError located at `option`.
  OutputSet(const std::filesystem::path& folder, std::vector<std::string> names,
            SourceLocation option = SourceLocation{"--out"});
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;
  // Removes the staging folder unless published.
  ~OutputSet();

  // Where the outputs are written until published.
  const std::filesystem::path& staging() const { return staging_; }
  const std::filesystem::path& folder() const { return folder_; }

  // Starts making the staged files or folders `paths` (committed; a folder with all it holds)
  // durable now, one after the other on a thread of their own that waits for the disk while the
  // command goes on: for outputs finished well before the rest, whose syncs would otherwise hold
  // up publish() at the end. publish() waits for them, throws the first error, and syncs the
  // rest of the folder. Where no thread can be started, they are synced at once. Threads may
  // call it at once.
  void sync_ahead(const std::vector<std::filesystem::path>& paths);

  // Makes the staged outputs the folder's, atomically. Throws InputError when the swap fails
  // (the previous set is then untouched).
  void publish();

 private:
  std::filesystem::path folder_;  // absolute, lexically normal
  std::filesystem::path staging_;
  SourceLocation option_;
  bool published_ = false;
  std::mutex ahead_mutex_;
  std::vector<std::future<void>> ahead_;             // sync_ahead's syncs, under ahead_mutex_
  std::vector<std::filesystem::path> synced_ahead_;  // what they sync, under ahead_mutex_
};

}  // namespace cwe
