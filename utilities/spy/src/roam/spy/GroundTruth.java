package roam.spy;

import java.util.Arrays;

/**
 * Every GROUND_TRUTH position received, in time order (a few MB even for hours of data), for
 * matching estimates by time: the position at utime t is interpolated linearly between the two
 * ground-truth rows around t, as roam-eval matches. Guarded by MapModel's lock.
 */
final class GroundTruth {
    private long[] utimes = new long[1024];
    private double[] xs = new double[1024];
    private double[] ys = new double[1024];
    private int size;

    void add(long utime, double x, double y) {
        if (!Double.isFinite(x) || !Double.isFinite(y)) return;
        if (size > 0 && utime <= utimes[size - 1]) return;  // out of order: keep the series sorted
        if (size == utimes.length) {
            utimes = Arrays.copyOf(utimes, 2 * size);
            xs = Arrays.copyOf(xs, 2 * size);
            ys = Arrays.copyOf(ys, 2 * size);
        }
        utimes[size] = utime;
        xs[size] = x;
        ys[size] = y;
        ++size;
    }

    void clear() {
        size = 0;
    }

    int size() {
        return size;
    }

    long firstUtime() {
        return utimes[0];
    }

    long lastUtime() {
        return utimes[size - 1];
    }

    boolean covers(long utime) {
        return size > 0 && utime >= utimes[0] && utime <= utimes[size - 1];
    }

    /** {x, y} at utime (which covers() must accept). */
    double[] at(long utime) {
        int i = Arrays.binarySearch(utimes, 0, size, utime);
        if (i >= 0) return new double[] {xs[i], ys[i]};
        i = -i - 1;  // utimes[i - 1] < utime < utimes[i]
        final double f = (double) (utime - utimes[i - 1]) / (double) (utimes[i] - utimes[i - 1]);
        return new double[] {xs[i - 1] + f * (xs[i] - xs[i - 1]), ys[i - 1] + f * (ys[i] - ys[i - 1])};
    }
}
