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
        return b.toString();
    }

    /** Why it failed, else the last rejection, else "". */
    static String rejection(estimator_status_t s) {
        if (s == null) return "";
        if (s.last_error != null && !s.last_error.isEmpty()) return "error: " + s.last_error;
        if (s.last_rejection != null && !s.last_rejection.isEmpty()) return "last rejected: " + s.last_rejection;
        return "";
    }

    /** Counts as integers, anything else to four significant digits. */
    static String number(double v) {
        if (v == Math.rint(v) && Math.abs(v) < 1e15) return Long.toString((long) v);
        return String.format("%.4g", v);
    }

    /** The estimator's own diagnostics (calibration values, solver cost, ...) as key=value. */
    static String[] diagnostics(estimator_status_t s) {
        if (s == null) return new String[0];
        final String[] pairs = new String[s.num_values];
        for (int i = 0; i < s.num_values; ++i) pairs[i] = s.keys[i] + "=" + number(s.values[i]);
        return pairs;
    }
}
