// The plugin build/hardsphereplugin.so registers every style of the table.

#include "hs_test_main.h"

#include "lammpsplugin.h"
#include "version.h"

#include <dlfcn.h>
#include <map>

#ifndef HS_PLUGIN_PATH
#error "HS_PLUGIN_PATH must be defined"
#endif

namespace {
struct Recorded {
  std::string style, version, author;
  bool has_creator;
  void *handle;
};
std::map<std::string, Recorded> recorded;    // key: "<style> <name>"
void *seen_lmp = nullptr;

void fake_regfunc(lammpsplugin_t *p, void *lmp)
{
  seen_lmp = lmp;
  recorded[std::string(p->style) + " " + p->name] = {
      p->style, p->version ? p->version : "", p->author ? p->author : "",
      p->creator.v2 != nullptr, p->handle};
}
}    // namespace

TEST(Plugin, RegistersAllStyles)
{
  // A live LAMMPS instance: like the lmp host, it also makes this executable
  // depend on liblammps (the plugin itself is not linked to it, as usual
  // for LAMMPS plugins, and needs e.g. typeinfo for LAMMPS_NS::Fix).
  HSLammps h;
  void *handle = dlopen(HS_PLUGIN_PATH, RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(handle, nullptr) << dlerror();
  auto init = (lammpsplugin_initfunc) dlsym(handle, "lammpsplugin_init");
  ASSERT_NE(init, nullptr) << dlerror();

  recorded.clear();
  (*init)((void *) h.lmp, handle, (void *) &fake_regfunc);

  const auto &styles = hardsphere_styles();
  EXPECT_EQ(recorded.size(), styles.size());
  for (const auto &s : styles) {
    const std::string key = std::string(s.kind) + " " + s.name;
    auto it = recorded.find(key);
    ASSERT_NE(it, recorded.end()) << "not registered by plugin: " << key;
    EXPECT_TRUE(it->second.has_creator) << key;
    EXPECT_EQ(it->second.version, LAMMPS_VERSION) << key;
    EXPECT_EQ(it->second.author, "HARDSPHERE developers");
    EXPECT_EQ(it->second.handle, handle);
  }
  if (!styles.empty()) EXPECT_EQ(seen_lmp, (void *) h.lmp);
  dlclose(handle);
}
