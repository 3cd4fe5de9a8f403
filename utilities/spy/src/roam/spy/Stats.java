package roam.spy;

import java.util.Arrays;
import java.util.concurrent.atomic.AtomicLong;

/**
 * How well the view keeps up: messages received, dropped (decoder queue full) and not decoded;
 * the lag from receipt to the model (over the newest 4096 messages); repaints per second and the
 * time a repaint takes. Printed by MapViewMain --stats and shown in the view's footer.
 */
final class Stats {
    final AtomicLong received = new AtomicLong();
    final AtomicLong dropped = new AtomicLong();
    final AtomicLong errors = new AtomicLong();
    final AtomicLong ignored = new AtomicLong();

    private final long[] lagsNs = new long[4096];
    private int lagCount;
    private int lagNext;
    private long lagMaxNs;

    private long paints;
    private long paintNsTotal;
    private long paintNsMax;
    private final long startNs = System.nanoTime();

    synchronized void recordLag(long ns) {
        lagsNs[lagNext] = ns;
        lagNext = (lagNext + 1) % lagsNs.length;
        lagCount = Math.min(lagCount + 1, lagsNs.length);
        lagMaxNs = Math.max(lagMaxNs, ns);
    }

    synchronized void recordPaint(long ns) {
        ++paints;
        paintNsTotal += ns;
        paintNsMax = Math.max(paintNsMax, ns);
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
        final double seconds = (System.nanoTime() - startNs) / 1e9;
        return String.format(
            "received %d, dropped %d, undecodable %d, backlog %d; lag median %.2f ms, p99 %.2f ms, max %.1f ms;"
                + " %d repaints (%.1f/s), %.1f ms mean, %.1f ms max",
            received.get(), dropped.get(), errors.get(), backlog, lag[0], lag[1], lagMaxNs / 1e6, paints,
            paints / Math.max(seconds, 1e-9), paints == 0 ? 0.0 : paintNsTotal / 1e6 / paints, paintNsMax / 1e6);
    }
}
