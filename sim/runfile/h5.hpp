// A thin RAII layer over the HDF5 C API: whole-array datasets and attributes,
// with errors that name the file and the object. HDF5's own error printing is
// switched off; every failure becomes a std::runtime_error.
#pragma once

#include <hdf5.h>

#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace dem2d::h5 {

// Owns one HDF5 identifier and closes it with the matching H5?close.
class Handle {
 public:
  Handle() = default;
  Handle(hid_t id, herr_t (*closer)(hid_t)) : id_(id), close_(closer) {}
  Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, H5I_INVALID_HID)), close_(o.close_) {}
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, H5I_INVALID_HID);
      close_ = o.close_;
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { reset(); }

  hid_t id() const { return id_; }
  operator hid_t() const { return id_; }  // NOLINT: pass straight to H5 calls
  void reset() { close(); }
  // Closes it; HDF5's status (< 0: failed).
  herr_t close() {
    const herr_t status = id_ >= 0 && close_ ? close_(id_) : 0;
    id_ = H5I_INVALID_HID;
    return status;
  }

 private:
  hid_t id_ = H5I_INVALID_HID;
  herr_t (*close_)(hid_t) = nullptr;
};

class File {
 public:
  static File create(const std::string& path);     // truncates
  static File open_read(const std::string& path);
  static File open_write(const std::string& path);  // existing file, read-write
  const std::string& path() const { return path_; }
  hid_t id() const { return h_.id(); }
  void flush() const;
  // Writes out what HDF5 still holds and closes the file; a std::runtime_error
  // naming it if that fails (a full disk). A writer closes with this before it
  // renames, never trusting the destructor, which cannot report.
  void close();

 private:
  static File adopt(const std::string& path, hid_t id, const char* failure);  // throws if id < 0
  Handle h_;
  std::string path_;
};

template <class T>
hid_t native_type();

// Writes `path` atomically: fill(file) into path + ".tmp", closed (checked),
// then renamed to path. On any failure the temporary file is removed and the
// error rethrown: `path` keeps what it held (a last good checkpoint is never
// replaced by an incomplete one).
template <class Fill>
void write_atomically(const std::string& path, Fill&& fill);

// Whole datasets. `dims` empty means 1-D of data.size(). Intermediate groups
// are created as needed. Large datasets are chunked and compressed.
template <class T>
void write(const File& f, const std::string& name, std::span<const T> data, std::vector<hsize_t> dims = {});
// Any contiguous array of a supported type (std::vector, AlignedVector, ...).
template <class Array>
void write(const File& f, const std::string& name, const Array& data, std::vector<hsize_t> dims = {}) {
  write(f, name, std::span<const typename Array::value_type>(data.data(), data.size()), std::move(dims));
}
void write_strings(const File& f, const std::string& name, const std::vector<std::string>& data);
// A scalar (rank-0) float64 dataset; read<double> gives it as one value.
void write_scalar(const File& f, const std::string& name, double value);

template <class T>
std::vector<T> read(const File& f, const std::string& name, std::vector<hsize_t>* dims = nullptr);
std::vector<std::string> read_strings(const File& f, const std::string& name);
std::vector<hsize_t> shape(const File& f, const std::string& name);
bool exists(const File& f, const std::string& name);
// The datasets in `group` and its subgroups, as paths relative to it ("energy/kinetic"), in name order.
std::vector<std::string> datasets_under(const File& f, const std::string& group);
// Its subgroups at every depth, the same way ("bodies", "bodies/0", ...).
std::vector<std::string> groups_under(const File& f, const std::string& group);
// Element type of a dataset as numpy spells it: "f8", "i4", "i8", "u1", ..., "str" or "other".
std::string dtype(const File& f, const std::string& name);

// Attributes on the object at `object` ("/" for the file).
void write_attr(const File& f, const std::string& object, const std::string& name, const std::string& value);
void write_attr(const File& f, const std::string& object, const std::string& name, double value);
void write_attr(const File& f, const std::string& object, const std::string& name, std::int64_t value);
std::string read_attr_string(const File& f, const std::string& object, const std::string& name);
double read_attr_double(const File& f, const std::string& object, const std::string& name);
std::int64_t read_attr_int(const File& f, const std::string& object, const std::string& name);
bool has_attr(const File& f, const std::string& object, const std::string& name);

void remove_quietly(const std::string& path);               // (no error if absent)
void rename_checked(const std::string& from, const std::string& to);  // std::runtime_error naming both

template <class Fill>
void write_atomically(const std::string& path, Fill&& fill) {
  const std::string tmp = path + ".tmp";
  try {
    File f = File::create(tmp);
    fill(static_cast<const File&>(f));
    f.close();
    rename_checked(tmp, path);
  } catch (...) {
    remove_quietly(tmp);
    throw;
  }
}

extern template void write<float>(const File&, const std::string&, std::span<const float>, std::vector<hsize_t>);
extern template std::vector<float> read<float>(const File&, const std::string&, std::vector<hsize_t>*);
extern template void write<double>(const File&, const std::string&, std::span<const double>, std::vector<hsize_t>);
extern template void write<std::int32_t>(const File&, const std::string&, std::span<const std::int32_t>, std::vector<hsize_t>);
extern template void write<std::int64_t>(const File&, const std::string&, std::span<const std::int64_t>, std::vector<hsize_t>);
extern template void write<std::uint8_t>(const File&, const std::string&, std::span<const std::uint8_t>, std::vector<hsize_t>);
extern template std::vector<double> read<double>(const File&, const std::string&, std::vector<hsize_t>*);
extern template std::vector<std::int32_t> read<std::int32_t>(const File&, const std::string&, std::vector<hsize_t>*);
extern template std::vector<std::int64_t> read<std::int64_t>(const File&, const std::string&, std::vector<hsize_t>*);
extern template std::vector<std::uint8_t> read<std::uint8_t>(const File&, const std::string&, std::vector<hsize_t>*);

}  // namespace dem2d::h5
