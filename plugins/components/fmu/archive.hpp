// An FMU's zip archive unpacked into a private temporary folder, removed with
// the object: the FMU's binary is dlopen'ed from there and its resources
// are handed to it by path (FMI 3.0, 2.5: the unpacked layout).
#pragma once

#include <string>

namespace fmu {

class UnpackedArchive {
 public:
  UnpackedArchive() = default;
  // Unpacks `archive` (a .fmu zip file) into a new folder mkdtemp made.
  // Throws std::runtime_error saying what failed, of "it" (the archive): no
  // such file, not a zip, an entry that would leave the folder ("..").
  explicit UnpackedArchive(const std::string& archive);
  ~UnpackedArchive();
  UnpackedArchive(const UnpackedArchive&) = delete;
  UnpackedArchive& operator=(const UnpackedArchive&) = delete;

  // Removes what the instance no longer needs once its binary is loaded and
  // it is instantiated: everything but resources/, and the whole folder when
  // the FMU has no resources. (A host may end its process without running
  // destructors, as `monohydra run`'s child does: then only resources stay.)
  void keep_only_resources();

  // The folder, without a trailing slash ("" before unpacking).
  const std::string& folder() const { return folder_; }

 private:
  std::string folder_;
};

}  // namespace fmu
