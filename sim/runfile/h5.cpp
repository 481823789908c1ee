#include "runfile/h5.hpp"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

namespace dem2d::h5 {

namespace {

// HDF5 as this layer uses it: its own error printing off (every failure
// becomes an exception naming the file), and no clean-up at exit: every file
// is closed explicitly (File::close, the Handles), and after a failed close
// (a full disk) HDF5's exit handler crashed on the broken file (SIGSEGV in
// H5F__close_cb, after the right error message had been printed).
struct LibrarySetup {
  LibrarySetup() {
    H5dont_atexit();
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
};
const LibrarySetup library_setup;

[[noreturn]] void fail(const File& f, const std::string& what) {
  throw std::runtime_error(f.path() + ": " + what);
}

Handle check(hid_t id, herr_t (*close)(hid_t), const File& f, const std::string& what) {
  if (id < 0) fail(f, what);
  return Handle(id, close);
}

void check(herr_t status, const File& f, const std::string& what) {
  if (status < 0) fail(f, what);
}

Handle link_create_plist() {
  Handle lcpl(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  H5Pset_create_intermediate_group(lcpl, 1);
  return lcpl;
}

// A C-string memory type for reading `stored`: variable or fixed `size`, with the
// stored character set (HDF5 does not convert between ASCII and UTF-8).
Handle string_type(hid_t stored, std::size_t size) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type, size);
  H5Tset_cset(type, H5Tget_cset(stored));
  return type;
}

Handle open_object(const File& f, const std::string& object) {
  return check(H5Oopen(f.id(), object.c_str(), H5P_DEFAULT), H5Oclose, f, "no object " + object);
}

Handle dataset_create_plist(const std::vector<hsize_t>& dims, std::size_t elem_size) {
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  hsize_t total = 1;
  for (hsize_t d : dims) total *= d;
  if (total * elem_size < (1u << 16) || dims.empty()) return dcpl;  // small: contiguous
  // chunks of ~256 KiB along the first dimension
  std::vector<hsize_t> chunk = dims;
  const hsize_t row = std::max<hsize_t>(1, total / std::max<hsize_t>(dims[0], 1)) * elem_size;
  chunk[0] = std::clamp<hsize_t>((1u << 18) / row, 1, dims[0]);
  H5Pset_chunk(dcpl, static_cast<int>(chunk.size()), chunk.data());
  H5Pset_shuffle(dcpl);
  H5Pset_deflate(dcpl, 1);
  return dcpl;
}

}  // namespace

File File::adopt(const std::string& path, hid_t id, const char* failure) {
  File f;
  f.path_ = path;
  f.h_ = check(id, H5Fclose, f, failure);
  return f;
}

File File::create(const std::string& path) {
  return adopt(path, H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), "cannot create the file");
}

namespace {

// An HDF5 file is a regular file: a pipe or a device would block or never end (HDF5 opens what it is given).
void require_regular(const std::string& path) {
  std::error_code ec;
  const auto st = std::filesystem::status(path, ec);  // (through links)
  if (ec || !std::filesystem::exists(st) || std::filesystem::is_regular_file(st)) return;  // (missing: HDF5 says so)
  const char* what = std::filesystem::is_directory(st) ? "a folder"
                     : std::filesystem::is_fifo(st)    ? "a pipe"
                     : std::filesystem::is_socket(st)  ? "a socket"
                                                       : "a device";
  throw std::runtime_error(path + ": " + what + ", not a regular file: an HDF5 file is one");
}

}  // namespace

File File::open_read(const std::string& path) {
  require_regular(path);
  return adopt(path, H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), "cannot open as HDF5 (missing or corrupt)");
}

File File::open_write(const std::string& path) {
  require_regular(path);
  return adopt(path, H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), "cannot open as HDF5 for writing");
}

void File::flush() const { check(H5Fflush(id(), H5F_SCOPE_GLOBAL), *this, "flush failed"); }

void File::close() {
  if (h_.id() < 0) return;
  const herr_t flushed = H5Fflush(h_.id(), H5F_SCOPE_LOCAL);
  const herr_t closed = h_.close();
  if (flushed < 0 || closed < 0)
    throw std::runtime_error(path_ + ": could not be written completely (HDF5 could not flush or close it: is the "
                                     "disk full?)");
}

void remove_quietly(const std::string& path) {
  std::error_code ec;
  std::filesystem::remove(path, ec);
}

void rename_checked(const std::string& from, const std::string& to) {
  std::error_code ec;
  std::filesystem::rename(from, to, ec);
  if (ec) throw std::runtime_error(to + ": cannot rename " + from + " to it (" + ec.message() + ")");
}

template <>
hid_t native_type<double>() { return H5T_NATIVE_DOUBLE; }
template <>
hid_t native_type<float>() { return H5T_NATIVE_FLOAT; }
template <>
hid_t native_type<std::int32_t>() { return H5T_NATIVE_INT32; }
template <>
hid_t native_type<std::int64_t>() { return H5T_NATIVE_INT64; }
template <>
hid_t native_type<std::uint8_t>() { return H5T_NATIVE_UINT8; }

template <class T>
void write(const File& f, const std::string& name, std::span<const T> data, std::vector<hsize_t> dims) {
  if (dims.empty()) dims = {data.size()};
  hsize_t total = 1;
  for (hsize_t d : dims) total *= d;
  if (total != data.size()) fail(f, name + ": data size does not match its dimensions");
  Handle space = check(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose,
                       f, name + ": bad dataspace");
  Handle lcpl = link_create_plist();
  Handle dcpl = dataset_create_plist(dims, sizeof(T));
  Handle ds = check(H5Dcreate2(f.id(), name.c_str(), native_type<T>(), space, lcpl, dcpl, H5P_DEFAULT),
                    H5Dclose, f, "cannot create dataset " + name);
  if (total > 0)
    check(H5Dwrite(ds, native_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()), f,
          "cannot write dataset " + name);
}

std::vector<hsize_t> shape(const File& f, const std::string& name) {
  Handle ds = check(H5Dopen2(f.id(), name.c_str(), H5P_DEFAULT), H5Dclose, f, "no dataset " + name);
  Handle space(H5Dget_space(ds), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space);
  std::vector<hsize_t> dims(static_cast<std::size_t>(std::max(rank, 0)));
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  return dims;
}

template <class T>
std::vector<T> read(const File& f, const std::string& name, std::vector<hsize_t>* dims_out) {
  const std::vector<hsize_t> dims = shape(f, name);
  hsize_t total = 1;
  for (hsize_t d : dims) total *= d;
  std::vector<T> data(total);
  Handle ds = check(H5Dopen2(f.id(), name.c_str(), H5P_DEFAULT), H5Dclose, f, "no dataset " + name);
  if (total > 0)
    check(H5Dread(ds, native_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()), f,
          "cannot read dataset " + name);
  if (dims_out) *dims_out = dims;
  return data;
}

void write_scalar(const File& f, const std::string& name, double value) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle lcpl = link_create_plist();
  Handle ds = check(H5Dcreate2(f.id(), name.c_str(), native_type<double>(), space, lcpl, H5P_DEFAULT, H5P_DEFAULT),
                    H5Dclose, f, "cannot create dataset " + name);
  check(H5Dwrite(ds, native_type<double>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &value), f, "cannot write dataset " + name);
}

void write_strings(const File& f, const std::string& name, const std::vector<std::string>& data) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type, H5T_VARIABLE);
  H5Tset_cset(type, H5T_CSET_UTF8);
  const hsize_t n = data.size();
  Handle space(H5Screate_simple(1, &n, nullptr), H5Sclose);
  Handle lcpl = link_create_plist();
  Handle ds = check(H5Dcreate2(f.id(), name.c_str(), type, space, lcpl, H5P_DEFAULT, H5P_DEFAULT),
                    H5Dclose, f, "cannot create dataset " + name);
  std::vector<const char*> ptrs;
  for (const auto& s : data) ptrs.push_back(s.c_str());
  if (n > 0)
    check(H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, ptrs.data()), f, "cannot write " + name);
}

std::vector<std::string> read_strings(const File& f, const std::string& name) {
  Handle ds = check(H5Dopen2(f.id(), name.c_str(), H5P_DEFAULT), H5Dclose, f, "no dataset " + name);
  Handle stored(H5Dget_type(ds), H5Tclose);
  Handle type = string_type(stored, H5T_VARIABLE);
  const std::vector<hsize_t> dims = shape(f, name);
  const hsize_t n = dims.empty() ? 0 : dims[0];
  std::vector<char*> ptrs(n, nullptr);
  if (n > 0)
    check(H5Dread(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, ptrs.data()), f, "cannot read " + name);
  std::vector<std::string> out(ptrs.begin(), ptrs.end());
  if (n > 0) {
    Handle space(H5Dget_space(ds), H5Sclose);
    H5Dvlen_reclaim(type, space, H5P_DEFAULT, ptrs.data());
  }
  return out;
}

bool exists(const File& f, const std::string& name) {
  // check each component so that a missing parent is not an error
  std::size_t pos = 0;
  while (true) {
    pos = name.find('/', pos + 1);
    const std::string part = name.substr(0, pos);
    if (!part.empty() && part != "/" && H5Lexists(f.id(), part.c_str(), H5P_DEFAULT) <= 0) return false;
    if (pos == std::string::npos) return true;
  }
}

namespace {

// The datasets (or, with `groups`, the groups) under `group`, their paths relative to it after `prefix`.
void collect(const File& f, hid_t group, const std::string& prefix, std::vector<std::string>& out, bool groups) {
  H5G_info_t info;
  if (H5Gget_info(group, &info) < 0) throw std::runtime_error(f.path() + ": cannot list group " + prefix);
  for (hsize_t k = 0; k < info.nlinks; ++k) {
    const ssize_t size = H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, k, nullptr, 0, H5P_DEFAULT);
    if (size < 0) throw std::runtime_error(f.path() + ": cannot list group " + prefix);
    std::string name(static_cast<std::size_t>(size) + 1, '\0');
    H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, k, name.data(), name.size(), H5P_DEFAULT);
    name.resize(static_cast<std::size_t>(size));
    Handle obj(H5Oopen(group, name.c_str(), H5P_DEFAULT), H5Oclose);
    if (obj.id() < 0) throw std::runtime_error(f.path() + ": cannot open " + prefix + name);
    if (H5Iget_type(obj) == H5I_GROUP) {
      if (groups) out.push_back(prefix + name);
      collect(f, obj, prefix + name + "/", out, groups);
    } else if (H5Iget_type(obj) == H5I_DATASET && !groups) {
      out.push_back(prefix + name);
    }
  }
}

}  // namespace

std::vector<std::string> datasets_under(const File& f, const std::string& group) {
  Handle g = check(H5Gopen2(f.id(), group.c_str(), H5P_DEFAULT), H5Gclose, f, "no group " + group);
  std::vector<std::string> out;
  collect(f, g, "", out, false);
  return out;
}

std::vector<std::string> groups_under(const File& f, const std::string& group) {
  Handle g = check(H5Gopen2(f.id(), group.c_str(), H5P_DEFAULT), H5Gclose, f, "no group " + group);
  std::vector<std::string> out;
  collect(f, g, "", out, true);
  return out;
}

std::string dtype(const File& f, const std::string& name) {
  Handle ds = check(H5Dopen2(f.id(), name.c_str(), H5P_DEFAULT), H5Dclose, f, "no dataset " + name);
  Handle type(H5Dget_type(ds), H5Tclose);
  const std::string size = std::to_string(H5Tget_size(type));
  switch (H5Tget_class(type)) {
    case H5T_FLOAT: return "f" + size;
    case H5T_INTEGER: return (H5Tget_sign(type) == H5T_SGN_NONE ? "u" : "i") + size;
    case H5T_STRING: return "str";
    default: return "other";
  }
}

// Variable-length UTF-8, which h5py reads as str (fixed-length ones come back as bytes).
void write_attr(const File& f, const std::string& object, const std::string& name, const std::string& value) {
  Handle obj = open_object(f, object);
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type, H5T_VARIABLE);
  H5Tset_cset(type, H5T_CSET_UTF8);
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  if (H5Aexists(obj, name.c_str()) > 0) H5Adelete(obj, name.c_str());
  Handle attr = check(H5Acreate2(obj, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose, f,
                      "cannot create attribute " + object + "@" + name);
  const char* text = value.c_str();
  check(H5Awrite(attr, type, &text), f, "cannot write attribute " + name);
}

namespace {
template <class T>
void write_scalar_attr(const File& f, const std::string& object, const std::string& name, T value) {
  Handle obj = open_object(f, object);
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  if (H5Aexists(obj, name.c_str()) > 0) H5Adelete(obj, name.c_str());
  Handle attr = check(H5Acreate2(obj, name.c_str(), native_type<T>(), space, H5P_DEFAULT, H5P_DEFAULT),
                      H5Aclose, f, "cannot create attribute " + object + "@" + name);
  check(H5Awrite(attr, native_type<T>(), &value), f, "cannot write attribute " + name);
}

template <class T>
T read_scalar_attr(const File& f, const std::string& object, const std::string& name) {
  Handle obj = open_object(f, object);
  Handle attr = check(H5Aopen(obj, name.c_str(), H5P_DEFAULT), H5Aclose, f,
                      "no attribute " + object + "@" + name);
  // one value: an array attribute would be read past `value` (a run file's damage, not a reader's overflow)
  Handle space(H5Aget_space(attr), H5Sclose);
  const hssize_t n = space.id() < 0 ? -1 : H5Sget_simple_extent_npoints(space);
  if (n != 1)
    throw std::runtime_error(f.path() + ": attribute " + object + "@" + name + " holds " + std::to_string(n) +
                             " values, expected one");
  T value{};
  check(H5Aread(attr, native_type<T>(), &value), f, "cannot read attribute " + name);
  return value;
}
}  // namespace

void write_attr(const File& f, const std::string& object, const std::string& name, double value) {
  write_scalar_attr(f, object, name, value);
}
void write_attr(const File& f, const std::string& object, const std::string& name, std::int64_t value) {
  write_scalar_attr(f, object, name, value);
}
double read_attr_double(const File& f, const std::string& object, const std::string& name) {
  return read_scalar_attr<double>(f, object, name);
}
std::int64_t read_attr_int(const File& f, const std::string& object, const std::string& name) {
  return read_scalar_attr<std::int64_t>(f, object, name);
}

std::string read_attr_string(const File& f, const std::string& object, const std::string& name) {
  Handle obj = open_object(f, object);
  Handle attr = check(H5Aopen(obj, name.c_str(), H5P_DEFAULT), H5Aclose, f,
                      "no attribute " + object + "@" + name);
  Handle ftype(H5Aget_type(attr), H5Tclose);
  if (H5Tis_variable_str(ftype) > 0) {
    Handle mtype = string_type(ftype, H5T_VARIABLE);
    char* buf = nullptr;
    check(H5Aread(attr, mtype, &buf), f, "cannot read attribute " + name);
    std::string out = buf ? buf : "";
    H5free_memory(buf);
    return out;
  }
  const std::size_t size = H5Tget_size(ftype);
  std::string buf(size, '\0');
  Handle mtype = string_type(ftype, size);
  check(H5Aread(attr, mtype, buf.data()), f, "cannot read attribute " + name);
  buf.resize(std::min(buf.size(), buf.find('\0')));
  return buf;
}

bool has_attr(const File& f, const std::string& object, const std::string& name) {
  Handle obj = open_object(f, object);
  return H5Aexists(obj, name.c_str()) > 0;
}

template void write<float>(const File&, const std::string&, std::span<const float>, std::vector<hsize_t>);
template std::vector<float> read<float>(const File&, const std::string&, std::vector<hsize_t>*);
template void write<double>(const File&, const std::string&, std::span<const double>, std::vector<hsize_t>);
template void write<std::int32_t>(const File&, const std::string&, std::span<const std::int32_t>, std::vector<hsize_t>);
template void write<std::int64_t>(const File&, const std::string&, std::span<const std::int64_t>, std::vector<hsize_t>);
template void write<std::uint8_t>(const File&, const std::string&, std::span<const std::uint8_t>, std::vector<hsize_t>);
template std::vector<double> read<double>(const File&, const std::string&, std::vector<hsize_t>*);
template std::vector<std::int32_t> read<std::int32_t>(const File&, const std::string&, std::vector<hsize_t>*);
template std::vector<std::int64_t> read<std::int64_t>(const File&, const std::string&, std::vector<hsize_t>*);
template std::vector<std::uint8_t> read<std::uint8_t>(const File&, const std::string&, std::vector<hsize_t>*);

}  // namespace dem2d::h5
