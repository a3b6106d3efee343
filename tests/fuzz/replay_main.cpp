// Runs a fuzz target's LLVMFuzzerTestOneInput once on every file under the given folders (the
// seed corpus and the committed findings), as libFuzzer would, and says how many it ran. A crash,
// a sanitizer report or an uncaught exception fails the run.
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  std::vector<fs::path> files;
  for (int a = 1; a < argc; ++a) {
    if (fs::is_regular_file(argv[a])) files.emplace_back(argv[a]);
    if (!fs::is_directory(argv[a])) continue;
    for (const auto& e : fs::recursive_directory_iterator(argv[a]))
      if (e.is_regular_file() && e.path().filename().string()[0] != '.') files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    std::ifstream in(f, std::ios::binary);
    const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                     std::istreambuf_iterator<char>());
    std::cout << "replay " << f.string() << " (" << bytes.size() << " bytes)" << std::endl;
    LLVMFuzzerTestOneInput(bytes.data(), bytes.size());
  }
  std::cout << files.size() << " inputs replayed" << std::endl;
  return files.empty() ? 1 : 0;
}
