// The paths of hs_test_paths.h, from CMake's compile definitions for this file only.

#include "hs_test_paths.h"

#if !defined(HS_LMP_BINARY) || !defined(HS_SOURCE_DIR) || !defined(HS_PLUGIN_PATH) || \
    !defined(HS_STOCK_LMP) || !defined(HS_OTHER_PLUGIN)
#error "unittest/CMakeLists.txt defines HS_LMP_BINARY, HS_SOURCE_DIR, HS_PLUGIN_PATH, HS_STOCK_LMP and HS_OTHER_PLUGIN for this file"
#endif

namespace hs_test_paths {
extern const char lmp_binary[] = HS_LMP_BINARY;
extern const char source_dir[] = HS_SOURCE_DIR;
extern const char plugin_path[] = HS_PLUGIN_PATH;
extern const char stock_lmp[] = HS_STOCK_LMP;
extern const char other_plugin[] = HS_OTHER_PLUGIN;
}    // namespace hs_test_paths
