// Dump the sphere positions (columns 0-2 of /rows/seaweed_particles) of a seaweed checkpoint to a
// raw file for cell_list_ab: uint64 rows, then rows x 3 doubles.
#include <hdf5.h>

#include <cstdio>
#include <vector>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: dump_positions <seaweed checkpoint.h5> <out.bin>\n");
    return 1;
  }
  const hid_t file = H5Fopen(argv[1], H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) return 1;
  const hid_t set = H5Dopen2(file, "/rows/seaweed_particles", H5P_DEFAULT);
  if (set < 0) return 1;
  hsize_t dims[2];
  H5Sget_simple_extent_dims(H5Dget_space(set), dims, nullptr);
  std::vector<double> rows(dims[0] * dims[1]);
  H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, rows.data());
  std::vector<double> pos(dims[0] * 3);
  for (hsize_t r = 0; r < dims[0]; ++r)
    for (int c = 0; c < 3; ++c) pos[r * 3 + c] = rows[r * dims[1] + c];
  FILE* out = std::fopen(argv[2], "wb");
  const unsigned long long n = dims[0];
  std::fwrite(&n, sizeof n, 1, out);
  std::fwrite(pos.data(), sizeof(double), pos.size(), out);
  std::fclose(out);
  std::printf("%llu positions\n", n);
  return 0;
}
