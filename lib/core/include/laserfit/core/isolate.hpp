#pragma once
// Third-party parsers (OpenCASCADE for STEP/IGES, assimp for the mesh formats, PCL for PCD and
// PLY clouds) read untrusted files in ways laserfit cannot fix: a corrupt file can crash them,
// corrupt their memory, make them loop, or make them allocate without bound. They therefore run
// in a forked child process with a wall-clock and a memory limit; the child hands its result
// back as bytes through an anonymous memory file, and whatever happens to it (signal, abort,
// exception, runaway) becomes one laserfit::Error naming the file, in the parent, which has
// written nothing. The caller decodes the bytes as untrusted input.
#include <functional>
#include <string>

namespace laserfit {

struct IsolationLimits {
  bool isolate = true;       // false: parse in this process (debugging a reader only)
  double timeout_s = 60.0;   // wall-clock limit of one read (s); 0: none
  double memory_mib = 8192;  // memory the reader may add to what it inherits (MiB); 0: none
};

// Runs `read` in a child process under `limits` and returns the bytes it returned. `reader`
// names the parser in messages ("the STEP reader crashed (signal 11, Segmentation fault)").
// Throws laserfit::Error naming `path` for a crash, a timeout, exhausted memory, or the
// reader's own error (its message passed through).
std::string run_isolated(const std::string& path, const std::string& reader,
                         const IsolationLimits& limits, const std::function<std::string()>& read);

}  // namespace laserfit
