#pragma once
// Deterministic randomness independent of the thread count: work is cut into fixed blocks and
// every block draws from its own generator seeded by (seed, stream, block). Which thread runs a
// block then cannot change a single bit of the output.
#include <cmath>
#include <cstdint>

namespace laserfit {

// SplitMix64 finaliser (Steele et al. 2014), used only to decorrelate seeds.
inline uint64_t mix_seed(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// The 64-bit Mersenne Twister (Nishimura & Matsumoto 2000), bit-for-bit std::mt19937_64 (tested
// against it), with a branch-free twist: libstdc++'s branches on the low bit of every word,
// which a CPU mispredicts half the time (6 ns per number against 1.7; the scanner draws ~6 per
// point). A UniformRandomBitGenerator: std distributions and algorithms take it.
class Mt19937_64 {
 public:
  using result_type = uint64_t;
  static constexpr result_type min() { return 0; }
  static constexpr result_type max() { return ~result_type(0); }

  explicit Mt19937_64(result_type seed = 5489u) {
    x_[0] = seed;
    for (int i = 1; i < kN; ++i)
      x_[i] = 6364136223846793005ull * (x_[i - 1] ^ (x_[i - 1] >> 62)) + uint64_t(i);
  }
  result_type operator()() {
    if (i_ >= kN) twist();
    uint64_t z = x_[i_++];
    z ^= (z >> 29) & 0x5555555555555555ull;
    z ^= (z << 17) & 0x71D67FFFEDA60000ull;
    z ^= (z << 37) & 0xFFF7EEE000000000ull;
    return z ^ (z >> 43);
  }

 private:
  static constexpr int kN = 312, kM = 156;
  static constexpr uint64_t kA = 0xB5026F5AA96619E9ull, kUpper = ~uint64_t(0) << 31;
  static uint64_t step(uint64_t a, uint64_t b, uint64_t c) {
    const uint64_t y = (a & kUpper) | (b & ~kUpper);
    return c ^ (y >> 1) ^ (-(y & 1) & kA);
  }
  void twist() {
    int k = 0;
    for (; k < kN - kM; ++k) x_[k] = step(x_[k], x_[k + 1], x_[k + kM]);
    for (; k < kN - 1; ++k) x_[k] = step(x_[k], x_[k + 1], x_[k + kM - kN]);
    x_[kN - 1] = step(x_[kN - 1], x_[0], x_[kM - 1]);
    i_ = 0;
  }
  uint64_t x_[kN];
  int i_ = kN;
};

inline Mt19937_64 block_rng(uint64_t seed, uint64_t stream, uint64_t block) {
  return Mt19937_64(mix_seed(mix_seed(mix_seed(seed) ^ stream) ^ block));
}

// Uniform double in [0, 1) from 53 random bits: std::uniform_real_distribution's output is
// implementation-defined, this is not, so files stay identical across standard libraries.
inline double uniform01(Mt19937_64& g) { return (g() >> 11) * 0x1.0p-53; }

// Standard normal by Box-Muller on uniform01 (again: the std distributions differ between
// standard libraries; this keeps noise bit-identical everywhere).
inline double gauss(Mt19937_64& g) {
  const double u1 = 1.0 - uniform01(g), u2 = uniform01(g);  // u1 in (0, 1]
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
}

// Standard normals in pairs by Marsaglia's polar method (one log, no trigonometry: the scanner
// draws millions per scan). Same determinism as gauss(): only the generator's state matters.
class NormalSource {
 public:
  explicit NormalSource(Mt19937_64& g) : g_(g) {}
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
  Mt19937_64& g_;
  double spare_ = 0;
  bool has_spare_ = false;
};

}  // namespace laserfit
