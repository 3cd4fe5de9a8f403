// A plugin whose descriptor has a different size (e.g. built from an edited header).
#include "roam/plugin_abi.h"

extern "C" __attribute__((visibility("default"))) const roam_plugin_descriptor* roam_plugin_entry(void) {
  static roam_plugin_descriptor descriptor{};
  descriptor.abi_version = ROAM_PLUGIN_ABI_VERSION;
  descriptor.descriptor_size = sizeof(roam_plugin_descriptor) - 8;
  descriptor.name = "wrong_size";
  return &descriptor;
}
