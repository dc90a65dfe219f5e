// One grid of a .vdb file, read by OpenVDB's own grid reader from a stream that throws at its first short read.
#pragma once
#include <openvdb/openvdb.h>

#include <string>

namespace mv::io {

// Reads grid `name` (empty: the first in the file) of the .vdb file at `path` and sets `name` to the grid's
// name; nullptr when the file holds no grids or none named `name` (matched as OpenVDB names it, or with the
// "[N]" suffix OpenVDB gives repeated names). Throws mv::Error when the file cannot be opened or read (it is
// read through io::FileStreambuf), and openvdb::Exception, std::ios_base::failure or std::bad_alloc as OpenVDB
// and the stream do (read_vdb turns them into mv::Error).
//
// Why not openvdb::io::File: its reader keeps going after its stream has run out. A damaged node count made it
// build hundreds of thousands of empty nodes from a 10 KB file (seconds and gigabytes per file under the fuzzer,
// BENCHMARKS.md "Fuzzing"); here the stream's exceptions stop it at the first read past the end. The grids
// before the wanted one are skipped by the offsets the file records (read when it records none, as files written
// by io::Stream); the wanted grid's parent is read too when the wanted grid is an instance (its tree is the parent's).
openvdb::GridBase::Ptr read_vdb_grid(const std::string& path, std::string& name);

}  // namespace mv::io
