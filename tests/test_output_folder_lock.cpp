// One live process per output folder (session/output_folder_lock.h). flock locks belong to the
// open file, so a second lock taken in this process stands for a second process.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <memory>

#include "session/output_folder_lock.h"

using rt::session::OutputFolderLock;

namespace {

std::filesystem::path fresh_folder(const std::string& name) {
  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / ("rt-lock-" + std::to_string(getpid())) / name;
  std::filesystem::remove_all(folder);
  return folder;
}

std::string refusal(const std::filesystem::path& folder) {
  try {
    OutputFolderLock second(folder, "--out");
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  return "";
}

}  // namespace

TEST_CASE("a second run in a live run's folder is refused, naming the folder, the holder and the option") {
  const std::filesystem::path folder = fresh_folder("busy");
  auto first = std::make_unique<OutputFolderLock>(folder, "--out");
  CHECK(std::filesystem::is_directory(folder));
  const std::string message = refusal(folder);
  CHECK(message.find(folder.string()) != std::string::npos);
  CHECK(message.find("in use by another running process (pid " + std::to_string(getpid()) + ")") != std::string::npos);
  CHECK(message.find("its own --out") != std::string::npos);
  // The holder's end frees the folder for the next run.
  first.reset();
  CHECK(refusal(folder).empty());
}

TEST_CASE("two folders are independent, and a folder left by a finished run is taken again") {
  const std::filesystem::path a = fresh_folder("site_A"), b = fresh_folder("site_B");
  OutputFolderLock lock_a(a, "--out");
  OutputFolderLock lock_b(b, "--out");
  { OutputFolderLock earlier(fresh_folder("done"), "--out"); }
  CHECK(refusal(a.parent_path() / "done").empty());
}

TEST_CASE("a link planted in place of the lock file is refused, not followed") {
  const std::filesystem::path folder = fresh_folder("planted");
  std::filesystem::create_directories(folder);
  const std::filesystem::path target = folder.parent_path() / "planted-target";
  std::filesystem::remove(target);
  std::filesystem::create_symlink(target, folder / ".lock");
  const std::string message = refusal(folder);
  CHECK(message.find("cannot use output folder " + folder.string()) != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(target));
}
