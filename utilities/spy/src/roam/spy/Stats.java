package roam.spy;

import java.util.Arrays;
import java.util.concurrent.atomic.AtomicLong;

/**
 * How well the view keeps up: messages received, dropped (decoder queue full) and not decoded;
 * the lag from receipt to the model (over the newest 4096 messages); repaints per second and the
 * time a repaint takes (over the last 5 s). Printed by MapViewMain --stats and shown in the view's footer.
 */
final class Stats {
    final AtomicLong received = new AtomicLong();
    final AtomicLong dropped = new AtomicLong();
    final AtomicLong errors = new AtomicLong();
    final AtomicLong ignored = new AtomicLong();
    final AtomicLong superseded = new AtomicLong();  // TRAJECTORY_ skipped: a newer one was queued

    // How late the view's Swing timer fires (newest 256 ticks): what anything on the Swing
    // thread, lcm-spy's table included, waits for.
    private final long[] swingDelayNs = new long[256];
    private int swingCount;
    private int swingNext;

    private final long[] lagsNs = new long[4096];
    private int lagCount;
    private int lagNext;
    private long lagMaxNs;

    private long paints;
    private long layers;
    private long paintNsMax;
    private long paintCpuNsTotal;
    // The newest repaints: when each started and how long it took (the rate and cost now).
    private final long[] paintAtNs = new long[64];
    private final long[] paintTookNs = new long[64];

    synchronized void recordSwingDelay(long ns) {
        swingDelayNs[swingNext] = Math.max(0, ns);
        swingNext = (swingNext + 1) % swingDelayNs.length;
        swingCount = Math.min(swingCount + 1, swingDelayNs.length);
    }

    /** {median, max} of the Swing timer's delay in ms over the newest ticks. */
    synchronized double[] swingDelayMs() {
        if (swingCount == 0) return new double[] {Double.NaN, Double.NaN};
        final long[] sorted = Arrays.copyOf(swingDelayNs, swingCount);
        Arrays.sort(sorted);
        return new double[] {sorted[swingCount / 2] / 1e6, sorted[swingCount - 1] / 1e6};
    }

    synchronized void recordLag(long ns) {
        lagsNs[lagNext] = ns;
        lagNext = (lagNext + 1) % lagsNs.length;
        lagCount = Math.min(lagCount + 1, lagsNs.length);
        lagMaxNs = Math.max(lagMaxNs, ns);
    }

    /** A frame drawn: wall and CPU time, and whether it needed a new layer (MapPainter.Layer). */
    synchronized void recordPaint(long ns, long cpuNs, boolean newLayer) {
        paintCpuNsTotal += cpuNs;
        if (newLayer) ++layers;
        final int i = (int) (paints % paintAtNs.length);
        paintAtNs[i] = System.nanoTime() - ns;
        paintTookNs[i] = ns;
        ++paints;
        paintNsMax = Math.max(paintNsMax, ns);
    }

    /** {repaints per second, mean ms per repaint} over the newest repaints of the last 5 s. */
    synchronized double[] paintRate() {
        final long now = System.nanoTime();
        int n = 0;
        long first = now, took = 0;
        for (int k = 1; k <= Math.min(paints, paintAtNs.length); ++k) {
            final int i = (int) ((paints - k) % paintAtNs.length);
            if (now - paintAtNs[i] > 5_000_000_000L) break;
            first = paintAtNs[i];
            took += paintTookNs[i];
            ++n;
        }
        if (n < 2) return new double[] {0, n == 0 ? Double.NaN : took / 1e6};
        return new double[] {(n - 1) / ((now - first) / 1e9), took / 1e6 / n};
    }

    /** {median, p99} lag in ms over the newest messages; NaN before any. */
    synchronized double[] lagMs() {
        if (lagCount == 0) return new double[] {Double.NaN, Double.NaN};
        final long[] sorted = Arrays.copyOf(lagsNs, lagCount);
        Arrays.sort(sorted);
        return new double[] {sorted[lagCount / 2] / 1e6, sorted[(int) Math.min(lagCount - 1, Math.floor(0.99 * lagCount))] / 1e6};
    }

    synchronized String line(int backlog) {
        final double[] lag = lagMs();
        final double[] paint = paintRate();
        final double[] swing = swingDelayMs();
        return String.format(
            "received %d, dropped %d, undecodable %d, superseded %d, backlog %d \u00B7 lag median %.2f ms, p99 %.2f ms,"
                + " max %.1f ms \u00B7 Swing timer late %.1f ms median, %.0f ms max"
                + " \u00B7 %.1f frames/s, %.1f ms each (max %.0f); all %d frames: %.1f ms CPU each, %d new layers",
            received.get(), dropped.get(), errors.get(), superseded.get(), backlog, lag[0], lag[1], lagMaxNs / 1e6,
            swing[0], swing[1], paint[0], paint[1],
            paintNsMax / 1e6, paints, paints == 0 ? 0.0 : paintCpuNsTotal / 1e6 / paints, layers);
    }
}
