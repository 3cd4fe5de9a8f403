// A plugin built against ABI-1's roam_odometry (24 bytes: no lateral motion, no covariance)
// whose descriptor claims the current version and size: the loader must refuse it by layout.
#include <cstring>

#include "roam/plugin_abi.h"

extern "C" __attribute__((visibility("default"))) const roam_plugin_descriptor* roam_plugin_entry(void) {
  static roam_plugin_descriptor descriptor{};
  const roam_struct_layout layouts[ROAM_ABI_NUM_STRUCTS] = ROAM_ABI_LAYOUTS;
  std::memcpy(descriptor.layouts, layouts, sizeof(layouts));
  descriptor.abi_version = ROAM_PLUGIN_ABI_VERSION;
  descriptor.descriptor_size = sizeof(roam_plugin_descriptor);
  descriptor.layouts[0].size = 24;
  descriptor.name = "wrong_layout";
  return &descriptor;
}
