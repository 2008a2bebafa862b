#include "session/output_folder_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace rt::session {
namespace {

// The holder's pid as it wrote it: digits only, and only as many as a pid has.
std::string holder_pid(int fd) {
  char text[16] = {};
  const ssize_t n = pread(fd, text, sizeof(text) - 1, 0);
  std::string pid;
  for (ssize_t i = 0; i < n && text[i] >= '0' && text[i] <= '9'; ++i) pid += text[i];
  return pid;
}

}  // namespace

OutputFolderLock::OutputFolderLock(const std::filesystem::path& folder, const std::string& option) {
  std::filesystem::create_directories(folder);
  const std::filesystem::path path = folder / ".lock";
  // O_NOFOLLOW: a link planted in the folder is refused, never written through.
  fd_ = open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
  if (fd_ < 0) throw std::runtime_error("cannot use output folder " + folder.string() + ": " + std::strerror(errno));
  if (flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    const std::string pid = error == EWOULDBLOCK ? holder_pid(fd_) : std::string();
    close(fd_);
    fd_ = -1;
    if (error != EWOULDBLOCK)
      throw std::runtime_error("cannot lock output folder " + folder.string() + ": " + std::strerror(error));
    throw std::runtime_error("output folder " + folder.string() + " is in use by another running process" +
                             (pid.empty() ? std::string() : " (pid " + pid + ")") + ": give this one its own " + option);
  }
  // The pid only makes a refused second process's message better: the lock holds without it.
  const std::string pid = std::to_string(getpid()) + "\n";
  if (ftruncate(fd_, 0) == 0 && pwrite(fd_, pid.data(), pid.size(), 0) < 0) errno = 0;
}

OutputFolderLock::~OutputFolderLock() {
  if (fd_ >= 0) close(fd_);
}

}  // namespace rt::session
