/* ----------------------------------------------------------------------
   HARDSPHERE package as a LAMMPS plugin (PLUGIN package, "plugin load").

   Built by CMake as build/hardsphereplugin.so from this file plus all
   package sources. Registers every entry of hardsphere_styles().
------------------------------------------------------------------------- */

#include "hardsphere_registry.h"

#include "lammpsplugin.h"
#include "version.h"

extern "C" void lammpsplugin_init(void *lmp, void *handle, void *regfunc)
{
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
