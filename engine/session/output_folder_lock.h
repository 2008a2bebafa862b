#pragma once
// One live process per output folder: two runs writing the same folder would mix their frames
// and leave one metrics.json. The lock is an flock on `FOLDER/.lock`, so the kernel releases it
// when the process ends however it ends, and a folder left by a finished run is free again.
#include <filesystem>
#include <string>

namespace rt::session {

class OutputFolderLock {
 public:
  // Creates `folder` where needed and holds it until destroyed. Throws std::runtime_error naming
  // the folder and the process that holds it; `option` is what the user changes to choose another
  // folder (e.g. "--out").
  OutputFolderLock(const std::filesystem::path& folder, const std::string& option);
  ~OutputFolderLock();
  OutputFolderLock(const OutputFolderLock&) = delete;
  OutputFolderLock& operator=(const OutputFolderLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace rt::session
