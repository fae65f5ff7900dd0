/* ----------------------------------------------------------------------
   HARDSPHERE package as a LAMMPS plugin (PLUGIN package, "plugin load").

   Built by CMake as build/hardsphereplugin.so from this file plus all
   package sources. Registers every entry of hardsphere_styles().

   The styles are compiled against the class layouts of one LAMMPS version
   (Fix, Modify, Neighbor, ... change between releases), so the plugin
   refuses to register into a LAMMPS of another version: it asks the host
   through the C library interface (lammps_version(), stable across
   versions) and stops with a message naming both versions (printed with
   lammps_error() and thrown as a LAMMPSException where the host has
   lammps_error(), LAMMPS >= 2023; else on stderr, registering nothing)
   instead of crashing later. A plugin built for a much older or newer LAMMPS usually
   does not even get this far: dlopen() fails on a missing symbol and
   LAMMPS reports "Open of file ... failed".
------------------------------------------------------------------------- */

#include "hardsphere_registry.h"

#include "exceptions.h"
#include "lammpsplugin.h"
#include "library.h"
#include "version.h"

#include <cstdio>
#include <dlfcn.h>
#include <string>

extern "C" void lammpsplugin_init(void *lmp, void *handle, void *regfunc)
{
#if defined(HS_LAMMPS_VERSION_NUMBER) && HS_LAMMPS_VERSION_NUMBER > 0
  const int host = lammps_version(lmp);
  if (host != HS_LAMMPS_VERSION_NUMBER) {
    const std::string msg = "HARDSPHERE plugin was compiled for LAMMPS " LAMMPS_VERSION " (" +
        std::to_string(HS_LAMMPS_VERSION_NUMBER) + ") but is loaded into LAMMPS " +
        std::to_string(host) +
        ": its styles depend on that version's classes; rebuild the plugin against the "
        "headers and library of this LAMMPS (see README, 'Your own LAMMPS')";
    using error_func = void (*)(void *, int, const char *);
    auto lmp_error = (error_func) dlsym(RTLD_DEFAULT, "lammps_error");
    if (lmp_error) {
      // the message on screen and in the log (as a warning: lammps_error()
      // with an error type would exit the process, also under Python), then
      // stop the command as error->all() does: LAMMPS' main() exits with 1,
      // a library or Python caller gets the error
      (*lmp_error)(lmp, 0 /* LMP_ERROR_WARNING */, msg.c_str());
      throw LAMMPS_NS::LAMMPSException("ERROR: " + msg);
    } else {
      fprintf(stderr, "ERROR: %s\n", msg.c_str());
      fflush(stderr);
    }
    return;    // register nothing
  }
#endif

  auto register_plugin = (lammpsplugin_regfunc) regfunc;

  for (const auto &s : hardsphere_styles()) {
    lammpsplugin_t plugin;
    plugin.version = LAMMPS_VERSION;
    plugin.style = s.kind;    // "fix" or "compute"
    plugin.name = s.name;
    plugin.info = "HARDSPHERE package style";
    plugin.author = "HARDSPHERE developers";
    plugin.creator.v2 = (lammpsplugin_factory2 *) s.creator;
    plugin.handle = handle;
    (*register_plugin)(&plugin, lmp);
  }
}
