// The isolated reader process (lib/cad/isolate): whatever a third-party parser does — crash,
// abort, loop, allocate without bound, throw — the caller gets one laserfit::Error naming the
// file; and the child's answer is decoded as untrusted bytes.
#include <gtest/gtest.h>

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "laserfit/cad/isolate.hpp"
#include "laserfit/core/error.hpp"
#include "test_util.hpp"

using namespace laserfit;
using cad::RawMesh;

namespace {

RawMesh tetra() {
  RawMesh raw;
  raw.mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  raw.mesh.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  raw.parts = {"tetra", "other"};
  raw.declared_to_mm = 25.4;
  raw.declared_unit = "INCH";
  raw.warnings = {"a warning"};
  return raw;
}

// The message read_isolated throws for `read`, or "" when it returns.
std::string error_of(const std::function<RawMesh()>& read, IsolationLimits limits = {}) {
  try {
    cad::read_isolated("part.step", "the STEP reader", limits, read);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

TEST(Isolate, ReturnsTheChildsMeshExactly) {
  const RawMesh raw = cad::read_isolated("part.step", "the STEP reader", {}, tetra);
  const RawMesh want = tetra();
  ASSERT_EQ(raw.mesh.vertices.size(), 4u);
  for (size_t i = 0; i < 4; ++i)
    EXPECT_EQ(raw.mesh.vertices[i], want.mesh.vertices[i]);  // bit-exact
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(raw.mesh.faces[i], want.mesh.faces[i]);
  EXPECT_EQ(raw.parts, want.parts);
  EXPECT_EQ(raw.declared_to_mm, 25.4);
  EXPECT_EQ(raw.declared_unit, "INCH");
  EXPECT_EQ(raw.warnings, want.warnings);
}

TEST(Isolate, ACrashIsAnErrorNamingFileReaderAndSignal) {
  const std::string e = error_of([]() -> RawMesh {
    std::raise(SIGSEGV);
    return {};
  });
  EXPECT_EQ(e, "part.step: the STEP reader crashed (signal 11, Segmentation fault)");
  EXPECT_TRUE(has(error_of([]() -> RawMesh { std::abort(); }), "crashed (signal 6"));
}

TEST(Isolate, TheReadersOwnErrorPassesThrough) {
  EXPECT_EQ(error_of([]() -> RawMesh { throw Error("part.step", "cannot parse"); }),
            "part.step: cannot parse");
  EXPECT_EQ(error_of([]() -> RawMesh { throw 42; }),
            "part.step: the STEP reader threw an unknown exception");
}

TEST(Isolate, ARunawayIsStoppedAtTheTimeout) {
  IsolationLimits limits;
  limits.timeout_s = 0.3;
  const auto t0 = std::chrono::steady_clock::now();
  const std::string e = error_of(
      []() -> RawMesh {
        for (;;) std::this_thread::sleep_for(std::chrono::milliseconds(10));
      },
      limits);
  const double waited =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(e,
            "part.step: the STEP reader took longer than 0.3 s (raise --timeout if the file is "
            "just large)");
  EXPECT_LT(waited, 5.0);  // killed near the deadline, not left running
}

TEST(Isolate, UnboundedAllocationIsStoppedAtTheMemoryLimit) {
  IsolationLimits limits;
  limits.memory_mib = 256;
  const std::string e = error_of(
      []() -> RawMesh {
        std::vector<std::vector<char>> hog;
        for (;;) hog.emplace_back(16 << 20, 1);  // touched, so resident too
      },
      limits);
  EXPECT_TRUE(has(e, "part.step: the STEP reader ")) << e;
  EXPECT_TRUE(has(e, "256 MiB")) << e;
}

// A reader forked while other threads allocate, start and end (a benchmark's workers) must not
// inherit a lock one of them held. A thread that ends hands its allocation caches back under the
// allocator's locks; under the sanitizer runtime of clang 14 a child forked meanwhile hung at its
// first allocation, at the first fork. Each read gets 20 s, far above the milliseconds it takes: a
// hang shows as a timeout.
TEST(Isolate, AReaderForkedWhileOtherThreadsAllocateDoesNotHang) {
  auto churn = [] {  // small blocks of many sizes: every size class of the allocator in use
    std::vector<std::string> v;
    for (int i = 0; i < 2000; ++i) v.emplace_back(size_t(16 + (i * 37) % 4000), 'x');
    return v.size();
  };
  std::atomic<bool> stop{false};
  std::atomic<size_t> sink{0};  // keeps the work from being optimised away
  std::vector<std::thread> busy;
  for (int t = 0; t < 2; ++t)
    busy.emplace_back([&] {
      while (!stop) std::thread([&] { sink += churn(); }).join();
    });
  IsolationLimits limits;
  limits.timeout_s = 20;
  int answered = 0;
  for (int i = 0; i < 20; ++i) {
    const std::string e = error_of(
        [&]() -> RawMesh {
          if (churn() != 2000) throw Error("part.step", "lost a block");
          return tetra();
        },
        limits);
    if (!e.empty()) {
      ADD_FAILURE() << "fork " << i << ": " << e;
      break;
    }
    ++answered;
  }
  stop = true;
  for (auto& t : busy) t.join();
  EXPECT_EQ(answered, 20);
}

TEST(Isolate, OffMeansInProcess) {
  IsolationLimits limits;
  limits.isolate = false;
  EXPECT_THROW(cad::read_isolated("part.step", "the STEP reader", limits,
                                  []() -> RawMesh { throw Error("in process"); }),
               Error);
}

TEST(RawMeshCodec, RoundTripsAndRefusesEveryTruncation) {
  const std::string bytes = cad::encode_raw_mesh(tetra());
  EXPECT_EQ(cad::encode_raw_mesh(cad::decode_raw_mesh(bytes, "f")), bytes);
  for (size_t n = 0; n < bytes.size(); ++n)
    EXPECT_THROW(cad::decode_raw_mesh(bytes.substr(0, n), "f"), Error) << n;
  EXPECT_THROW(cad::decode_raw_mesh(bytes + "x", "f"), Error);
}

TEST(RawMeshCodec, RefusesHugeCountsAndBadIndicesBeforeAllocating) {
  std::string bytes = cad::encode_raw_mesh(tetra());
  std::string huge = bytes;
  const uint64_t n = uint64_t(1) << 60;  // vertex count right after the 8-byte magic
  std::memcpy(huge.data() + 8, &n, sizeof n);
  EXPECT_THROW(cad::decode_raw_mesh(huge, "f"), Error);
  RawMesh bad = tetra();
  bad.mesh.faces[2] = {0, 1, 4};  // vertex 4 of 4
  EXPECT_THROW(cad::decode_raw_mesh(cad::encode_raw_mesh(bad), "f"), Error);
  bad.mesh.faces[2] = {0, -1, 2};
  EXPECT_THROW(cad::decode_raw_mesh(cad::encode_raw_mesh(bad), "f"), Error);
}
