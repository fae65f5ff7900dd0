/* -*- c++ -*- ----------------------------------------------------------
   Where this build's programs and the repository are (absolute paths).

   Defined in hs_test_paths.cpp, the one object compiled with these paths
   (CMake's compile definitions HS_LMP_BINARY, ...): the test programs' own
   objects then do not depend on where the clone lives, so scripts/setup.sh's
   compiler cache reuses them in a fresh clone. Constant-initialised arrays,
   so tests may read them in their own static initialisers.
------------------------------------------------------------------------- */

#ifndef HS_TEST_PATHS_H
#define HS_TEST_PATHS_H

namespace hs_test_paths {
extern const char lmp_binary[];      // build/lmp
extern const char source_dir[];      // repository root
extern const char plugin_path[];     // build/hardsphereplugin.so
extern const char stock_lmp[];       // stock lmp with PLUGIN for this LAMMPS, "" if none
extern const char other_plugin[];    // the plugin built for the other LAMMPS version, or ""
}    // namespace hs_test_paths

#endif
