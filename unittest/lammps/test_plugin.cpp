// The plugin build/hardsphereplugin.so registers every style of the table.

#include "hs_test_main.h"

#include "lammpsplugin.h"
#include "version.h"

#include <dlfcn.h>
#include <map>

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
  void *handle = dlopen(hs_test_paths::plugin_path, RTLD_NOW | RTLD_LOCAL);
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

// The plugin's styles depend on one LAMMPS version's classes: loaded into a
// LAMMPS that reports another version (lammps_version(), here faked through
// the instance's num_ver), it registers nothing and says why; with LAMMPS
// >= 2023 it stops with a LAMMPS error (an exception), as error->all() would.
TEST(Plugin, RefusesOtherLammpsVersion)
{
  HSLammps h;
  void *handle = dlopen(hs_test_paths::plugin_path, RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(handle, nullptr) << dlerror();
  auto init = (lammpsplugin_initfunc) dlsym(handle, "lammpsplugin_init");
  ASSERT_NE(init, nullptr) << dlerror();

  const int real_version = h.lmp->num_ver;
  h.lmp->num_ver = real_version - 10000;    // one year older
  recorded.clear();
  std::string message;
  testing::internal::CaptureStderr();
  try {
    (*init)((void *) h.lmp, handle, (void *) &fake_regfunc);
  } catch (std::exception &e) {
    message = e.what();
  }
  const std::string err = testing::internal::GetCapturedStderr();
  h.lmp->num_ver = real_version;
  if (message.empty()) message = err;
  EXPECT_TRUE(recorded.empty()) << "registered " << recorded.size() << " styles";
  EXPECT_NE(message.find("HARDSPHERE plugin was compiled for LAMMPS " LAMMPS_VERSION), std::string::npos)
      << message;
  EXPECT_NE(message.find(std::to_string(real_version - 10000)), std::string::npos) << message;
  EXPECT_NE(message.find("rebuild the plugin"), std::string::npos) << message;
#if defined(HS_LAMMPS_ALWAYS_EXCEPTIONS) && HS_LAMMPS_ALWAYS_EXCEPTIONS
  EXPECT_NE(message.find("ERROR: "), std::string::npos) << "expected the LAMMPS error: " << message;
#endif
  dlclose(handle);
}
