/* ----------------------------------------------------------------------
   HARDSPHERE package: style table + registration (see hardsphere_registry.h)
------------------------------------------------------------------------- */

#include "hardsphere_registry.h"

#include "compute.h"
#include "fix.h"
#include "lammps.h"
#include "modify.h"

#include <string>

// First pass: the generated headers include every fix_*.h / compute_*.h
// that declares a style, *without* FIX_CLASS / COMPUTE_CLASS, which yields
// the class declarations (the FixStyle(...) block sits in the #ifdef branch,
// the class in the #else branch). Empty generated headers are fine.
#include "style_hardsphere_compute.h"    // IWYU pragma: keep
#include "style_hardsphere_fix.h"        // IWYU pragma: keep

using namespace LAMMPS_NS;

namespace {
template <class T> void *hs_creator(void *lmp, int narg, char **arg)
{
  return new T((LAMMPS_NS::LAMMPS *) lmp, narg, arg);
}
}    // namespace

const std::vector<HSStyleEntry> &hardsphere_styles()
{
  // Second pass, as in LAMMPS' modify.cpp: with FIX_CLASS / COMPUTE_CLASS
  // defined each header expands only to its FixStyle(...)/ComputeStyle(...)
  // lines, which we turn into table entries.
  // Statements, not a braced list: each header's line is "FixStyle(...);".
  static const std::vector<HSStyleEntry> table = [] {
    std::vector<HSStyleEntry> t;
#define FIX_CLASS
#define FixStyle(key, Class) t.push_back(HSStyleEntry{"fix", #key, &hs_creator<Class>})
#include "style_hardsphere_fix.h"    // IWYU pragma: keep
#undef FixStyle
#undef FIX_CLASS

#define COMPUTE_CLASS
#define ComputeStyle(key, Class) t.push_back(HSStyleEntry{"compute", #key, &hs_creator<Class>})
#include "style_hardsphere_compute.h"    // IWYU pragma: keep
#undef ComputeStyle
#undef COMPUTE_CLASS
    return t;
  }();
  return table;
}

void hardsphere_register_styles(LAMMPS *lmp)
{
  // Same casts as the PLUGIN package (plugin.cpp) uses for creator.v2.
  // NOTE: "clear" re-creates Modify and drops these entries (see header).
  for (const auto &s : hardsphere_styles()) {
    const std::string kind(s.kind);
    if (kind == "fix") {
      (*lmp->modify->fix_map)[s.name] = (Modify::FixCreator) s.creator;
    } else if (kind == "compute") {
      (*lmp->modify->compute_map)[s.name] = (Modify::ComputeCreator) s.creator;
    }
  }
}
