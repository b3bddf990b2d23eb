#include "contact/fclib_problem_format.h"

#include "contact/whole_blocks.h"

#include <hdf5.h>
#include <hdf5_hl.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <vector>

namespace csim {
namespace {

[[noreturn]] void fail(const std::string& dataset, const std::string& message) {
  throw std::runtime_error(dataset + ": " + message);
}

// The file, closed however the reading ends; HDF5's own error printing is off while it is open.
class File {
 public:
  explicit File(const std::string& path) {
    H5Eget_auto2(H5E_DEFAULT, &saved_handler_, &saved_data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    id_ = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    if (id_ < 0) {
      H5Eset_auto2(H5E_DEFAULT, saved_handler_, saved_data_);
      throw std::runtime_error("cannot open as an HDF5 file");
    }
  }
  ~File() {
    H5Fclose(id_);
    H5Eset_auto2(H5E_DEFAULT, saved_handler_, saved_data_);
  }
  File(const File&) = delete;
  File& operator=(const File&) = delete;

  bool has(const char* name) const { return H5Lexists(id_, name, H5P_DEFAULT) > 0; }

  // The number of elements of a dataset of rank 0 or 1.
  long long count(const std::string& name) const {
    if (!has(name.c_str())) fail(name, "missing");
    int rank = 0;
    if (H5LTget_dataset_ndims(id_, name.c_str(), &rank) < 0 || rank > 1) fail(name, "not a scalar or a vector");
    hsize_t dimensions[1] = {1};
    H5T_class_t type_class;
    std::size_t type_size = 0;
    if (H5LTget_dataset_info(id_, name.c_str(), rank ? dimensions : nullptr, &type_class, &type_size) < 0)
      fail(name, "unreadable");
    return rank ? static_cast<long long>(dimensions[0]) : 1;
  }

  // The first `expected` values (the read fills the whole dataset, which may hold more).
  std::vector<int> integers(const std::string& name, long long expected) const {
    std::vector<int> values(static_cast<std::size_t>(stored_count(name, expected)));
    if (!values.empty() && H5LTread_dataset_int(id_, name.c_str(), values.data()) < 0)
      fail(name, "unreadable as integers");
    values.resize(static_cast<std::size_t>(expected));
    return values;
  }

  int integer(const std::string& name) const { return integers(name, 1)[0]; }

  std::vector<double> numbers(const std::string& name, long long expected) const {
    std::vector<double> values(static_cast<std::size_t>(stored_count(name, expected)));
    if (!values.empty() && H5LTread_dataset_double(id_, name.c_str(), values.data()) < 0)
      fail(name, "unreadable as numbers");
    values.resize(static_cast<std::size_t>(expected));
    for (const double value : values)
      if (!std::isfinite(value)) fail(name, "a non-finite value");
    return values;
  }

 private:
  // The dataset's size, at least `expected` (FCLib writes nzmax values of which fewer may be used).
  long long stored_count(const std::string& name, long long expected) const {
    const long long found = count(name);
    if (found < expected) fail(name, std::to_string(found) + " values, expected " + std::to_string(expected));
    return found;
  }

  hid_t id_ = -1;
  H5E_auto2_t saved_handler_ = nullptr;
  void* saved_data_ = nullptr;
};

void check_index(const std::string& dataset, int index, int size) {
  if (index < 0 || index >= size)
    fail(dataset, "index " + std::to_string(index) + " outside 0 to " + std::to_string(size - 1));
}

}  // namespace

bool is_hdf5_file(const std::string& path) {
  char signature[8] = {};
  std::ifstream(path, std::ios::binary).read(signature, sizeof signature);
  return std::memcmp(signature, "\x89HDF\r\n\x1a\n", sizeof signature) == 0;
}

FrictionContactProblem read_fclib_problem(const std::string& path) {
  const File file(path);
  if (!file.has("/fclib_local")) {
    if (file.has("/fclib_global")) fail("/fclib_global", "a global problem (M, H, f, w), which csim does not read");
    fail("/fclib_local", "missing: not an FCLib problem");
  }
  if (file.has("/fclib_local/V") || file.has("/fclib_local/R"))
    fail("/fclib_local/V", "a local problem with bilateral constraints (V, R, s), which csim does not read");
  FrictionContactProblem problem;
  problem.dimension = file.integer("/fclib_local/spacedim");
  if (problem.dimension != 2 && problem.dimension != 3)
    fail("/fclib_local/spacedim", std::to_string(problem.dimension) + ", expected 2 or 3");
  const int m = file.integer("/fclib_local/W/m"), n = file.integer("/fclib_local/W/n");
  if (m != n || m <= 0 || m % problem.dimension != 0)
    fail("/fclib_local/W", std::to_string(m) + " × " + std::to_string(n) +
                               ", expected a square matrix of a multiple of spacedim rows");
  problem.contacts = m / problem.dimension;
  const int nz = file.integer("/fclib_local/W/nz");
  const int stored = nz >= 0 ? nz : file.integer("/fclib_local/W/nzmax");
  if (nz < -2 || stored < 0) fail("/fclib_local/W/nz", std::to_string(nz) + ": not a CSparse storage");

  std::vector<Eigen::Triplet<double>> entries;
  if (nz >= 0) {
    const std::vector<int> rows = file.integers("/fclib_local/W/i", nz);
    const std::vector<int> columns = file.integers("/fclib_local/W/p", nz);
    const std::vector<double> values = file.numbers("/fclib_local/W/x", nz);
    for (int k = 0; k < nz; ++k) {
      check_index("/fclib_local/W/i", rows[k], m);
      check_index("/fclib_local/W/p", columns[k], m);
      entries.emplace_back(rows[k], columns[k], values[k]);
    }
  } else {
    const std::vector<int> starts = file.integers("/fclib_local/W/p", m + 1);
    if (starts[0] != 0) fail("/fclib_local/W/p", "does not start at 0");
    for (int outer = 0; outer < m; ++outer)
      if (starts[outer + 1] < starts[outer] || starts[outer + 1] > stored)
        fail("/fclib_local/W/p", "entry " + std::to_string(outer + 1) + " out of order or past nzmax");
    const std::vector<int> inner = file.integers("/fclib_local/W/i", starts[m]);
    const std::vector<double> values = file.numbers("/fclib_local/W/x", starts[m]);
    for (int outer = 0; outer < m; ++outer)
      for (int k = starts[outer]; k < starts[outer + 1]; ++k) {
        check_index("/fclib_local/W/i", inner[k], m);
        if (nz == -1) entries.emplace_back(inner[k], outer, values[k]);  // compressed columns
        else entries.emplace_back(outer, inner[k], values[k]);           // compressed rows
      }
  }
  problem.storage = DelassusStorage::sparse;
  problem.W_sparse = whole_blocks(m, problem.dimension, entries);

  const std::vector<double> q = file.numbers("/fclib_local/vectors/q", m);
  problem.b = Eigen::Map<const Eigen::VectorXd>(q.data(), m);
  const std::vector<double> mu = file.numbers("/fclib_local/vectors/mu", problem.contacts);
  for (const double value : mu) {
    if (value < 0.0) fail("/fclib_local/vectors/mu", "a negative friction coefficient");
    problem.mu.emplace_back(value, value);
  }
  return problem;
}

}  // namespace csim
