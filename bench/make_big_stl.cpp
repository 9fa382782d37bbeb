// Writes a closed bumpy torus as a binary STL of at most FACES faces and near it (never fewer
// than 18), streamed row by row (no mesh in memory), for the big-mesh measurements of
// docs/collision.md §13 (bench/big_mesh.sh):
//   make_big_stl FACES OUT.stl [MAJOR_MM]
// The same surface as bench::make_torus_with_faces (minor radius MAJOR / 3, bump 0.15); every
// vertex is computed once per row in float, so shared vertices are bit-identical and the loader
// welds them into a closed mesh.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numbers>
#include <vector>

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: make_big_stl FACES OUT.stl [MAJOR_MM]\n");
    return 1;
  }
  const double faces = std::atof(argv[1]);
  const double major = argc > 3 ? std::atof(argv[3]) : 1000, minor = major / 3, bump = 0.15;
  const int nv = std::max(3, static_cast<int>(std::lround(std::sqrt(faces / 4.0))));
  // Rounded down: FACES at the loader's face limit must stay loadable (10^7 gave 10,001,406).
  const int nu = std::max(3, static_cast<int>(std::floor(faces / (2.0 * nv))));
  const std::uint32_t n = 2u * static_cast<std::uint32_t>(nu) * static_cast<std::uint32_t>(nv);
  std::FILE* f = std::fopen(argv[2], "wb");
  if (!f) {
    std::perror(argv[2]);
    return 1;
  }
  char header[80] = {};
  std::snprintf(header, sizeof header, "bumpy torus %d x %d, major %g mm", nu, nv, major);
  std::fwrite(header, 1, 80, f);
  std::fwrite(&n, 4, 1, f);
  const double two_pi = 2 * std::numbers::pi;
  auto row = [&](int i, std::vector<float>& out) {
    out.resize(3 * static_cast<std::size_t>(nv));
    for (int j = 0; j < nv; ++j) {
      const double u = two_pi * (i % nu) / nu, v = two_pi * j / nv;
      const double r = minor * (1 + bump * std::sin(5 * u) * std::sin(3 * v));
      out[3 * j] = static_cast<float>((major + r * std::cos(v)) * std::cos(u));
      out[3 * j + 1] = static_cast<float>((major + r * std::cos(v)) * std::sin(u));
      out[3 * j + 2] = static_cast<float>(r * std::sin(v));
    }
  };
  std::vector<float> a, b, first;
  row(0, a);
  first = a;
  std::vector<char> buf;
  for (int i = 0; i < nu; ++i) {
    if (i + 1 < nu) row(i + 1, b);
    else b = first;  // the same bits as row 0
    buf.clear();
    auto put = [&](const float* p, const float* q, const float* r) {
      char rec[50] = {};
      std::memcpy(rec + 12, p, 12);
      std::memcpy(rec + 24, q, 12);
      std::memcpy(rec + 36, r, 12);
      buf.insert(buf.end(), rec, rec + 50);
    };
    for (int j = 0; j < nv; ++j) {
      const int k = (j + 1) % nv;
      const float *pa = &a[3 * j], *pb = &b[3 * j], *pc = &b[3 * k], *pd = &a[3 * k];
      put(pa, pb, pc);
      put(pa, pc, pd);
    }
    std::fwrite(buf.data(), 1, buf.size(), f);
    std::swap(a, b);
  }
  if (std::fclose(f) != 0) {
    std::perror(argv[2]);
    return 1;
  }
  std::printf("%s: %u faces (%d x %d)\n", argv[2], n, nu, nv);
  return 0;
}
