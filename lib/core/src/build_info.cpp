#include "laserfit/core/build_info.hpp"

#include <elf.h>
#include <link.h>

#include <cstdio>
#include <cstring>

namespace laserfit {
namespace {

// The main executable is the first object dl_iterate_phdr reports; its PT_NOTE segments hold
// the NT_GNU_BUILD_ID note.
int find_build_id(dl_phdr_info* info, size_t, void* out) {
  auto& id = *static_cast<std::string*>(out);
  for (int i = 0; i < info->dlpi_phnum; ++i) {
    const ElfW(Phdr)& ph = info->dlpi_phdr[i];
    if (ph.p_type != PT_NOTE) continue;
    const char* p = reinterpret_cast<const char*>(info->dlpi_addr + ph.p_vaddr);
    const char* end = p + ph.p_memsz;
    while (p + sizeof(ElfW(Nhdr)) <= end) {
      const auto* n = reinterpret_cast<const ElfW(Nhdr)*>(p);
      const char* name = p + sizeof(ElfW(Nhdr));
      const char* desc = name + ((n->n_namesz + 3) & ~3u);
      if (n->n_type == NT_GNU_BUILD_ID && n->n_namesz == 4 && std::memcmp(name, "GNU", 4) == 0) {
        for (unsigned k = 0; k < n->n_descsz; ++k) {
          char hex[3];
          std::snprintf(hex, sizeof hex, "%02x", static_cast<unsigned char>(desc[k]));
          id += hex;
        }
        return 1;
      }
      p = desc + ((n->n_descsz + 3) & ~3u);
    }
  }
  return 1;  // only the first object, the executable
}

}  // namespace

std::string build_info() {
  std::string id;
  dl_iterate_phdr(find_build_id, &id);
  return std::string("laserfit ") + kVersion + " (build-id " + (id.empty() ? "unknown" : id) + ")";
}

}  // namespace laserfit
