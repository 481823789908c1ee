#include "runfile/h5_seal.hpp"

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/fnv.hpp"

namespace dem2d::h5 {

namespace {

constexpr const char* kSeal = "content_hash";

struct Walk {
  const File* file;
  Fnv1a* fnv;
  std::string path;  // of the object whose attributes are being walked
};

[[noreturn]] void checksum_failed(const File& f, const std::string& what) {
  throw std::runtime_error(f.path() + ": cannot checksum " + what);
}

// The values of an attribute or a dataset: strings as text, numbers as their native bytes.
template <class Read>
void add_values(const File& f, hid_t type, hid_t space, Fnv1a& fnv, const std::string& what, Read read) {
  const hssize_t points = H5Sget_simple_extent_npoints(space);
  if (points < 0) checksum_failed(f, what);
  if (H5Tget_class(type) == H5T_STRING) {
    Handle mem(H5Tcopy(type), H5Tclose);  // the file's character set: HDF5 converts none
    if (H5Tis_variable_str(type) > 0) {
      std::vector<char*> text(static_cast<std::size_t>(points), nullptr);
      if (read(mem.id(), text.data()) < 0) checksum_failed(f, what);
      for (char* s : text) fnv.add(std::string(s ? s : "")), H5free_memory(s);
      return;
    }
    std::vector<char> bytes(static_cast<std::size_t>(points) * H5Tget_size(type));
    if (read(mem.id(), bytes.data()) < 0) checksum_failed(f, what);
    fnv.add(bytes.data(), bytes.size());
    return;
  }
  Handle mem(H5Tget_native_type(type, H5T_DIR_ASCEND), H5Tclose);
  std::vector<unsigned char> bytes(static_cast<std::size_t>(points) * H5Tget_size(mem));
  if (!bytes.empty() && read(mem.id(), bytes.data()) < 0) checksum_failed(f, what);
  fnv.add(bytes.data(), bytes.size());
}

herr_t add_attribute(hid_t object, const char* name, const H5A_info_t*, void* data) {
  Walk& w = *static_cast<Walk*>(data);
  const std::string attribute(name);
  if (w.path == "/" && attribute == kSeal) return 0;
  w.fnv->add("@", 1);
  w.fnv->add(attribute);
  Handle attr(H5Aopen(object, name, H5P_DEFAULT), H5Aclose);
  Handle type(H5Aget_type(attr), H5Tclose), space(H5Aget_space(attr), H5Sclose);
  const std::string what = "attribute " + w.path + "@" + attribute;
  if (attr.id() < 0 || type.id() < 0 || space.id() < 0) checksum_failed(*w.file, what);
  add_values(*w.file, type, space, *w.fnv, what,
             [&](hid_t mem, void* buf) { return H5Aread(attr, mem, buf); });
  return 0;
}

void add_attributes(const File& f, hid_t object, const std::string& path, Fnv1a& fnv) {
  Walk w{&f, &fnv, path};
  hsize_t idx = 0;
  if (H5Aiterate2(object, H5_INDEX_NAME, H5_ITER_INC, &idx, add_attribute, &w) < 0) checksum_failed(f, "the attributes of " + path);
}

void add_group(const File& f, hid_t group, const std::string& path, Fnv1a& fnv) {
  add_attributes(f, group, path, fnv);
  H5G_info_t info;
  if (H5Gget_info(group, &info) < 0) checksum_failed(f, "group " + path);
  for (hsize_t k = 0; k < info.nlinks; ++k) {
    const ssize_t size = H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, k, nullptr, 0, H5P_DEFAULT);
    if (size < 0) checksum_failed(f, "the links of " + path);
    std::string name(static_cast<std::size_t>(size) + 1, '\0');
    H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, k, name.data(), name.size(), H5P_DEFAULT);
    name.resize(static_cast<std::size_t>(size));
    const std::string child = (path == "/" ? "/" : path + "/") + name;
    fnv.add(child);
    Handle obj(H5Oopen(group, name.c_str(), H5P_DEFAULT), H5Oclose);
    if (obj.id() < 0) checksum_failed(f, child);
    if (H5Iget_type(obj) == H5I_GROUP) {
      add_group(f, obj, child, fnv);
    } else if (H5Iget_type(obj) == H5I_DATASET) {
      add_attributes(f, obj, child, fnv);
      Handle type(H5Dget_type(obj), H5Tclose), space(H5Dget_space(obj), H5Sclose);
      if (type.id() < 0 || space.id() < 0) checksum_failed(f, "dataset " + child);
      const int rank = H5Sget_simple_extent_ndims(space);
      std::vector<hsize_t> dims(static_cast<std::size_t>(std::max(rank, 0)));
      H5Sget_simple_extent_dims(space, dims.data(), nullptr);
      fnv.add(dims.data(), dims.size() * sizeof(hsize_t));
      add_values(f, type, space, fnv, "dataset " + child,
                 [&](hid_t mem, void* buf) { return H5Dread(obj, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf); });
    }
  }
}

}  // namespace

std::uint64_t content_hash(const File& f) {
  Fnv1a fnv;
  Handle root(H5Gopen2(f.id(), "/", H5P_DEFAULT), H5Gclose);
  if (root.id() < 0) checksum_failed(f, "the root group");
  add_group(f, root, "/", fnv);
  return fnv.h;
}

namespace {
std::string content_hash_hex(const File& f) { return Fnv1a{content_hash(f)}.hex(); }
}  // namespace

void seal(const File& f) { write_attr(f, "/", kSeal, content_hash_hex(f)); }

void check_seal(const File& f) {
  if (!has_attr(f, "/", kSeal)) throw std::runtime_error(f.path() + ": no content checksum (content_hash): not written whole");
  const std::string stored = read_attr_string(f, "/", kSeal), now = content_hash_hex(f);
  if (stored != now)
    throw std::runtime_error(f.path() + ": its content does not match its checksum (" + now + ", written " + stored +
                             "): the file is damaged");
}

}  // namespace dem2d::h5
