package roam.spy;

import java.util.Arrays;

/**
 * A path that keeps at most {@code cap} points however long the run: when full, every other
 * point is dropped and from then on only every second (fourth, ...) point is kept, so the
 * stored points stay spread evenly over the whole path. The newest point is always kept apart
 * (the "tail"), so a drawn path reaches the current position. Not thread-safe: MapModel locks.
 */
final class DecimatedPath {
    private final int cap;
    private long[] utimes;
    private double[] xs;
    private double[] ys;
    private int size;
    private long stride = 1;
    private long seen;
    private boolean hasTail;
    private long tailUtime;
    private double tailX;
    private double tailY;

    DecimatedPath(int cap) {
        this.cap = Math.max(4, cap & ~1);
        utimes = new long[16];
        xs = new double[16];
        ys = new double[16];
    }

    void add(long utime, double x, double y) {
        if (!Double.isFinite(x) || !Double.isFinite(y)) return;
        hasTail = true;
        tailUtime = utime;
        tailX = x;
        tailY = y;
        if (seen++ % stride != 0) return;
        if (size == cap) {
            for (int i = 0; i < cap / 2; ++i) {  // keep points 0, 2, 4, ...
                utimes[i] = utimes[2 * i];
                xs[i] = xs[2 * i];
                ys[i] = ys[2 * i];
            }
            size = cap / 2;
            stride *= 2;
        }
        if (size == xs.length) {
            final int grown = Math.min(cap, 2 * size);
            utimes = Arrays.copyOf(utimes, grown);
            xs = Arrays.copyOf(xs, grown);
            ys = Arrays.copyOf(ys, grown);
        }
        utimes[size] = utime;
        xs[size] = x;
        ys[size] = y;
        ++size;
    }

    void clear() {
        size = 0;
        stride = 1;
        seen = 0;
        hasTail = false;
    }

    /** Number of stored points (the tail not counted). */
    int size() {
        return size;
    }

    boolean isEmpty() {
        return !hasTail;
    }

    long lastUtime() {
        return tailUtime;
    }

    double lastX() {
        return tailX;
    }

    double lastY() {
        return tailY;
    }

    /** The stored points plus the tail, as one polyline: {xs, ys, utimes} (utimes exact as doubles). */
    double[][] copyPolyline() {
        final boolean addTail = hasTail && (size == 0 || utimes[size - 1] != tailUtime);
        final int n = size + (addTail ? 1 : 0);
        final double[] x = Arrays.copyOf(xs, n);
        final double[] y = Arrays.copyOf(ys, n);
        final double[] t = new double[n];
        for (int i = 0; i < size; ++i) t[i] = utimes[i];
        if (addTail) {
            x[n - 1] = tailX;
            y[n - 1] = tailY;
            t[n - 1] = tailUtime;
        }
        return new double[][] {x, y, t};
    }
}
