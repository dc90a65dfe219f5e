// assimp's file access routed through megavox's file layer (io/file_ops.h): the files assimp opens for a mesh
// (the mesh, an OBJ's material library, ...) are read by io::open_read and io::read_some, so the test seams
// there -- injected read faults, memory files -- reach them too.
#pragma once
#include <assimp/IOSystem.hpp>

#include <string>

namespace mv::io {

// Read-only: assimp's attempts to write get nullptr. A read error is not thrown through assimp (whose importers
// are not written for foreign exceptions): the stream reports a short read, and error() keeps the first such
// message ("PATH: read error: ...") for the caller to report instead of what assimp made of the file. So does a
// file that ends before the size it had when opened (assimp would read the part as the whole).
class AssimpFiles final : public Assimp::IOSystem {
 public:
  bool Exists(const char* path) const override;
  char getOsSeparator() const override { return '/'; }
  Assimp::IOStream* Open(const char* path, const char* mode = "rb") override;
  void Close(Assimp::IOStream* stream) override;
  // The first read error of any stream opened here; empty when there was none.
  const std::string& error() const { return error_; }

 private:
  std::string error_;
};

}  // namespace mv::io
