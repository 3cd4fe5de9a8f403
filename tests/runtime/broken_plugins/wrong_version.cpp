// A plugin built against a future ABI: the loader must refuse it by version.
#include "roam/plugin_abi.h"

extern "C" __attribute__((visibility("default"))) const roam_plugin_descriptor* roam_plugin_entry(void) {
  static roam_plugin_descriptor descriptor{};
  descriptor.abi_version = ROAM_PLUGIN_ABI_VERSION + 1;
  descriptor.descriptor_size = sizeof(roam_plugin_descriptor);
  descriptor.name = "wrong_version";
  return &descriptor;
}
