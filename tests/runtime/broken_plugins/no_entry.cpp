// A shared object that is not a roam plugin: no roam_plugin_entry symbol.
extern "C" __attribute__((visibility("default"))) int some_other_function(void) { return 42; }
