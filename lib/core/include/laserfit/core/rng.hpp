#pragma once
// Deterministic randomness independent of the thread count: work is cut into fixed blocks and
// every block draws from its own generator seeded by (seed, stream, block). Which thread runs a
// block then cannot change a single bit of the output.
#include <cmath>
#include <cstdint>
#include <random>

namespace laserfit {

// SplitMix64 finaliser (Steele et al. 2014), used only to decorrelate seeds.
inline uint64_t mix_seed(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

inline std::mt19937_64 block_rng(uint64_t seed, uint64_t stream, uint64_t block) {
  return std::mt19937_64(mix_seed(mix_seed(mix_seed(seed) ^ stream) ^ block));
}

// Uniform double in [0, 1) from 53 random bits: std::uniform_real_distribution's output is
// implementation-defined, this is not, so files stay identical across standard libraries.
inline double uniform01(std::mt19937_64& g) { return (g() >> 11) * 0x1.0p-53; }

// Standard normal by Box-Muller on uniform01 (again: the std distributions differ between
// standard libraries; this keeps noise bit-identical everywhere).
inline double gauss(std::mt19937_64& g) {
  const double u1 = 1.0 - uniform01(g), u2 = uniform01(g);  // u1 in (0, 1]
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
}

// Standard normals in pairs by Marsaglia's polar method (one log, no trigonometry: the scanner
// draws millions per scan). Same determinism as gauss(): only the generator's state matters.
class NormalSource {
 public:
  explicit NormalSource(std::mt19937_64& g) : g_(g) {}
  double operator()() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u, v, s;
    do {
      u = 2.0 * uniform01(g_) - 1.0;
      v = 2.0 * uniform01(g_) - 1.0;
      s = u * u + v * v;
    } while (s >= 1.0 || s == 0.0);
    const double f = std::sqrt(-2.0 * std::log(s) / s);
    spare_ = v * f;
    has_spare_ = true;
    return u * f;
  }

 private:
  std::mt19937_64& g_;
  double spare_ = 0;
  bool has_spare_ = false;
};

}  // namespace laserfit
