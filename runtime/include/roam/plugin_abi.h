/*
 * roam plugin ABI: the C boundary between roam-run and an estimator plugin.
 *
 * A plugin is a shared object exporting one function,
 *
 *     const roam_plugin_descriptor* roam_plugin_entry(void);
 *
 * that returns a descriptor with static storage. The host checks `abi_version`,
 * `descriptor_size` and the size and alignment of every struct in `layouts` before touching
 * anything else, then calls `create` once per
 * configured instance. Every call returns a status (ROAM_OK or ROAM_ERROR); on error the
 * instance's `last_error` tells why. No C++ exception may cross this boundary.
 *
 * Pointers returned by poll_* / describe_config stay valid until the next call on the
 * same instance. All strings are UTF-8 and NUL-terminated. Units: metres, radians,
 * microseconds of the data's own clock.
 *
 * C++ plugins do not implement this by hand: they derive from roam::Estimator and use
 * ROAM_DEFINE_PLUGIN (roam/plugin_shim.hpp), which catches, stores and reports errors.
 */
#ifndef ROAM_PLUGIN_ABI_H_
#define ROAM_PLUGIN_ABI_H_

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Bump on any change to the structs or function table below. */
#define ROAM_PLUGIN_ABI_VERSION 3u
#define ROAM_PLUGIN_ENTRY_SYMBOL "roam_plugin_entry"

#define ROAM_OK 0
#define ROAM_ERROR 1

enum roam_state {
  ROAM_STATE_INITIALIZING = 0,
  ROAM_STATE_TRACKING = 1,
  ROAM_STATE_FINISHED = 2,
  ROAM_STATE_FAILED = 3
};

/* An SE(2) step in the robot frame at its start: forward, lateral (left), heading change. */
typedef struct roam_odometry {
  int64_t utime; /* end of the step */
  double forward_m;
  double lateral_m;
  double delta_heading_rad;
  double covariance[9]; /* row-major over (forward, lateral, heading); NaN where unknown */
  int32_t robot;        /* the team member whose step it is (index into set_team's robots; 0 alone) */
} roam_odometry;

typedef struct roam_range {
  int64_t utime;
  int32_t beacon_id;
  int32_t has_bearing; /* 0 or 1 */
  double range_m;
  double sigma_m; /* <= 0: the estimator's configured value */
  double bearing_rad;
  int32_t robot;    /* the team member that measured it (0 alone) */
  int32_t to_robot; /* 0: to the fixed beacon beacon_id; k > 0: to team member k - 1 (so a
                       zero-filled range is a beacon's) */
} roam_range;

typedef struct roam_pose {
  int64_t utime;
  double x_m;
  double y_m;
  double heading_rad;
  double covariance[9]; /* row-major over (x, y, heading); NaN where unknown */
  int32_t robot;        /* the team member it is a pose of (0 alone) */
} roam_pose;

typedef struct roam_beacon {
  int32_t id;
  double x_m;
  double y_m;
  double covariance[4]; /* row-major over (x, y); NaN where unknown */
} roam_beacon;

typedef struct roam_kv {
  const char* key;
  const char* value;
} roam_kv;

/* Filled by create() when it fails: which config key (may be empty) and why. */
typedef struct roam_error {
  char key[128];
  char message[1024];
} roam_error;

typedef struct roam_status {
  int32_t state; /* enum roam_state */
  int64_t odometry_accepted;
  int64_t odometry_rejected;
  int64_t ranges_accepted;
  int64_t ranges_rejected;
  const char* last_rejection; /* "" if none */
  int32_t num_values;         /* estimator-specific diagnostics */
  const char* const* keys;
  const double* values;
} roam_status;

typedef void* roam_handle;

/* sizeof and alignof of one struct that crosses the boundary, as the plugin was compiled. */
typedef struct roam_struct_layout {
  uint32_t size;
  uint32_t align;
} roam_struct_layout;

/* The structs in roam_plugin_descriptor.layouts, in this order. */
#define ROAM_ABI_NUM_STRUCTS 7
#define ROAM_ABI_STRUCT_NAMES \
  { "roam_odometry", "roam_range", "roam_pose", "roam_beacon", "roam_kv", "roam_error", "roam_status" }
#ifdef __cplusplus
#define ROAM_ALIGNOF(T) alignof(T)
#else
#define ROAM_ALIGNOF(T) _Alignof(T)
#endif
#define ROAM_LAYOUT_OF(T) { (uint32_t)sizeof(T), (uint32_t)ROAM_ALIGNOF(T) }
#define ROAM_ABI_LAYOUTS                                                                         \
  {                                                                                              \
    ROAM_LAYOUT_OF(roam_odometry), ROAM_LAYOUT_OF(roam_range), ROAM_LAYOUT_OF(roam_pose),        \
        ROAM_LAYOUT_OF(roam_beacon), ROAM_LAYOUT_OF(roam_kv), ROAM_LAYOUT_OF(roam_error),        \
        ROAM_LAYOUT_OF(roam_status)                                                              \
  }

typedef struct roam_plugin_descriptor {
  uint32_t abi_version;     /* ROAM_PLUGIN_ABI_VERSION */
  uint32_t descriptor_size; /* sizeof(roam_plugin_descriptor) */
  /* ROAM_ABI_LAYOUTS: the host rejects a plugin whose structs differ from its own. */
  roam_struct_layout layouts[ROAM_ABI_NUM_STRUCTS];
  const char* name;         /* e.g. "spectral" */
  const char* description;  /* one line */

  /* Creates an instance from its config section (keys other than `plugin`).
   * Returns NULL and fills *error on failure. */
  roam_handle (*create)(const roam_kv* config, int32_t num_config, roam_error* error);
  void (*destroy)(roam_handle h);
  /* The effective configuration, defaults included, for --print-config. */
  int (*describe_config)(roam_handle h, const roam_kv** config, int32_t* num_config);

  int (*set_initial_pose)(roam_handle h, const roam_pose* pose);
  int (*set_beacons)(roam_handle h, const roam_beacon* beacons, int32_t num_beacons);
  int (*add_odometry)(roam_handle h, const roam_odometry* odometry);
  int (*add_range)(roam_handle h, const roam_range* range);
  /* End of input: smoothers run their final solve here. */
  int (*finish)(roam_handle h);

  /* Poses produced since the last call (0, 1 or several), oldest first. */
  int (*poll_poses)(roam_handle h, const roam_pose** poses, int32_t* num_poses);
  /* *changed = 1 and the whole map if it changed since the last call. */
  int (*poll_map)(roam_handle h, int32_t* changed, const roam_beacon** beacons,
                  int32_t* num_beacons);
  /* The whole path. force = 1 at the end of input and on the host's periodic request;
   * *available = 0 if the estimator has no path to give yet. */
  int (*poll_trajectory)(roam_handle h, int32_t force, int32_t* available,
                         const roam_pose** poses, int32_t* num_poses);
  int (*get_status)(roam_handle h, roam_status* status);
  /* Why the last call failed; "" if it did not. Never NULL. */
  const char* (*last_error)(roam_handle h);
  /* NULL: the plugin estimates one robot (a team run gives each robot an instance of its own).
   * Otherwise it estimates a team: called once, before any input, with the team's robot names;
   * inputs then carry `robot` (and a range `other_robot`), and poses name their robot. */
  int (*set_team)(roam_handle h, const char* const* robots, int32_t num_robots);
} roam_plugin_descriptor;

typedef const roam_plugin_descriptor* (*roam_plugin_entry_fn)(void);

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* ROAM_PLUGIN_ABI_H_ */
