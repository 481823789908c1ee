// A checksum over an HDF5 file's whole content, for the files a run writes
// to resume from (checkpoint, segments): every group's and dataset's path,
// every attribute's value and every dataset's values, in name order
// (FNV-1a, 64 bits). HDF5 notices a damaged structure, not damaged values:
// bytes changed inside a dataset read back as other numbers. A sealed file
// whose content no longer matches its checksum is refused.
#pragma once

#include <cstdint>

#include "runfile/h5.hpp"

namespace dem2d::h5 {

// The checksum of the content (the root attribute `content_hash` left out).
std::uint64_t content_hash(const File& f);

// Writes the root attribute `content_hash` (the last thing written to f).
void seal(const File& f);

// std::runtime_error naming the file if it has no seal or its content does not match it.
void check_seal(const File& f);

}  // namespace dem2d::h5
