package roam.spy;

import roam.estimator_status_t;

/** The readout lines of one estimator: its error now, and its STATUS_ message in words. */
final class StatusText {
    private StatusText() {}

    static String state(byte state) {
        switch (state) {
            case estimator_status_t.INITIALIZING: return "initializing";
            case estimator_status_t.TRACKING: return "tracking";
            case estimator_status_t.FINISHED: return "finished";
            case estimator_status_t.FAILED: return "FAILED";
            default: return "state " + state;
        }
    }

    /** "error 1.23 m at t=456.7 s", or why there is none. */
    static String error(MapModel.Track t, boolean truthOnBus) {
        if (!t.hasPose) return "no pose yet";
        if (!truthOnBus) return "no GROUND_TRUTH on the bus";
        if (!Double.isFinite(t.errorM)) return "error: no ground truth at its time";
        return String.format("error %.2f m at t=%.1f s", t.errorM, t.errorUtime / 1e6);
    }

    /** State, accepted / rejected counts, CPU, last rejection or error. */
    static String status(estimator_status_t s) {
        if (s == null) return "no STATUS_ yet";
        final StringBuilder b = new StringBuilder(state(s.state));
        b.append(String.format(" \u00B7 odometry %d/%d rej \u00B7 ranges %d/%d rej \u00B7 cpu %.2f s",
                               s.odometry_accepted, s.odometry_rejected, s.ranges_accepted, s.ranges_rejected,
                               s.cpu_total_s));
        if (s.last_error != null && !s.last_error.isEmpty()) b.append(" \u00B7 error: ").append(s.last_error);
        else if (s.last_rejection != null && !s.last_rejection.isEmpty()) b.append(" \u00B7 last rejected: ").append(s.last_rejection);
        return b.toString();
    }

    /** The estimator's own diagnostics (calibration values, solver cost, ...) as key=value. */
    static String diagnostics(estimator_status_t s) {
        if (s == null || s.num_values == 0) return "";
        final StringBuilder b = new StringBuilder();
        for (int i = 0; i < s.num_values; ++i) {
            if (b.length() > 0) b.append("  ");
            b.append(s.keys[i]).append('=').append(String.format("%.4g", s.values[i]));
        }
        return b.toString();
    }
}
