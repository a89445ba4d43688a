/// \file h5_tool.cpp
/// \brief Test helper for run_faults.py (no h5py on the test machines):
///   h5_tool set-int <file> <attribute> <value>   overwrite a root integer attribute
///   h5_tool same <a> <b> <dataset>               exit 0 if the double datasets are bitwise equal
///   h5_tool same-rows <a> <b> <dataset>          the same for 2-D datasets taken as sets of rows
///   h5_tool max-diff-rows <a> <b> <dataset> <key> largest |a - b| of each column, rows matched by
///                                                the bits of column <key> (e.g. a particle id)
///                                                (particle rows, whose order depends on the ranks)
///   h5_tool layout <file> <dataset>              print "chunked AxBxC filters shuffle,deflate" or
///                                                "contiguous filters none"
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

std::vector<double> read_all(const char* file, const char* name, std::vector<hsize_t>& dims) {
  hid_t f = H5Fopen(file, H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return {};
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // a missing dataset is reported by the caller
  hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
  if (d < 0) {
    H5Fclose(f);
    return {};
  }
  hid_t s = H5Dget_space(d);
  dims.resize(H5Sget_simple_extent_ndims(s));
  H5Sget_simple_extent_dims(s, dims.data(), nullptr);
  hsize_t n = 1;
  for (auto x : dims) n *= x;
  std::vector<double> v(n);
  H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Sclose(s);
  H5Dclose(d);
  H5Fclose(f);
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 5 && std::string(argv[1]) == "set-int") {
    hid_t f = H5Fopen(argv[2], H5F_ACC_RDWR, H5P_DEFAULT);
    if (f < 0) return 1;
    long long v = std::atoll(argv[4]);
    hid_t a = H5Aopen(f, argv[3], H5P_DEFAULT);
    const herr_t st = H5Awrite(a, H5T_NATIVE_LLONG, &v);
    H5Aclose(a);
    H5Fclose(f);
    return st < 0;
  }
  if (argc == 5 && std::string(argv[1]) == "same") {
    std::vector<hsize_t> da, db;
    auto a = read_all(argv[2], argv[4], da), b = read_all(argv[3], argv[4], db);
    if (a.empty() || da != db) {
      std::printf("%s: missing or different shapes\n", argv[4]);
      return 1;
    }
    std::size_t differ = 0;
    for (std::size_t i = 0; i < a.size(); ++i) differ += std::memcmp(&a[i], &b[i], 8) != 0;
    std::printf("%s: %zu of %zu values differ\n", argv[4], differ, a.size());
    return differ != 0;
  }
  if (argc == 5 && std::string(argv[1]) == "same-rows") {
    std::vector<hsize_t> da, db;
    auto a = read_all(argv[2], argv[4], da), b = read_all(argv[3], argv[4], db);
    if (a.empty() || da != db || da.size() != 2) {
      std::printf("%s: missing, not 2-D or different shapes\n", argv[4]);
      return 1;
    }
    // Rows as bit patterns, sorted: equal multisets of rows give equal sorted lists.
    const std::size_t w = da[1];
    auto rows = [w](const std::vector<double>& v) {
      std::vector<std::vector<std::uint64_t>> r(v.size() / w, std::vector<std::uint64_t>(w));
      for (std::size_t i = 0; i < v.size(); ++i) std::memcpy(&r[i / w][i % w], &v[i], 8);
      std::sort(r.begin(), r.end());
      return r;
    };
    const auto ra = rows(a), rb = rows(b);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < ra.size(); ++i) differ += ra[i] != rb[i];
    std::printf("%s: %zu of %zu rows differ\n", argv[4], differ, ra.size());
    return differ != 0;
  }
  if (argc == 6 && std::string(argv[1]) == "max-diff-rows") {
    std::vector<hsize_t> da, db;
    auto a = read_all(argv[2], argv[4], da), b = read_all(argv[3], argv[4], db);
    const std::size_t key = std::stoul(argv[5]);
    if (a.empty() || da != db || da.size() != 2 || key >= da[1]) {
      std::printf("%s: missing, not 2-D, different shapes or no column %zu\n", argv[4], key);
      return 1;
    }
    const std::size_t w = da[1], n = da[0];
    auto order = [&](const std::vector<double>& v) {
      std::vector<std::pair<std::uint64_t, std::size_t>> o(n);
      for (std::size_t r = 0; r < n; ++r) {
        std::memcpy(&o[r].first, &v[r * w + key], 8);
        o[r].second = r;
      }
      std::sort(o.begin(), o.end());
      return o;
    };
    const auto oa = order(a), ob = order(b);
    std::vector<double> worst(w, 0.0);
    for (std::size_t k = 0; k < n; ++k) {
      if (oa[k].first != ob[k].first) {
        std::printf("%s: the key columns differ\n", argv[4]);
        return 1;
      }
      for (std::size_t c = 0; c < w; ++c)
        worst[c] = std::max(worst[c], std::abs(a[oa[k].second * w + c] - b[ob[k].second * w + c]));
    }
    std::printf("%s: largest |a - b| per column:", argv[4]);
    for (std::size_t c = 0; c < w; ++c) std::printf(" %.3g", worst[c]);
    std::printf("\n");
    return 0;
  }
  if (argc == 4 && std::string(argv[1]) == "layout") {
    hid_t f = H5Fopen(argv[2], H5F_ACC_RDONLY, H5P_DEFAULT);
    if (f < 0) return 1;
    hid_t d = H5Dopen2(f, argv[3], H5P_DEFAULT);
    if (d < 0) return 1;
    hid_t p = H5Dget_create_plist(d);
    std::string out;
    if (H5Pget_layout(p) == H5D_CHUNKED) {
      hsize_t c[8] = {};
      const int n = H5Pget_chunk(p, 8, c);
      out = "chunked ";
      for (int i = 0; i < n; ++i) out += (i ? "x" : "") + std::to_string(c[i]);
    } else {
      out = "contiguous";
    }
    const int nf = H5Pget_nfilters(p);
    out += " filters ";
    if (nf == 0) out += "none";
    for (int i = 0; i < nf; ++i) {
      const H5Z_filter_t id = H5Pget_filter2(p, i, nullptr, nullptr, nullptr, 0, nullptr, nullptr);
      out += std::string(i ? "," : "") + (id == H5Z_FILTER_DEFLATE   ? "deflate"
                                          : id == H5Z_FILTER_SHUFFLE ? "shuffle"
                                                                     : std::to_string(id));
    }
    std::printf("%s\n", out.c_str());
    H5Pclose(p);
    H5Dclose(d);
    H5Fclose(f);
    return 0;
  }
  std::fprintf(stderr,
               "usage: h5_tool set-int <file> <attr> <value> | same|same-rows <a> <b> <dataset> | "
               "max-diff-rows <a> <b> <dataset> <key column> | layout <file> <dataset>\n");
  return 2;
}
