package roam.spy;

import roam.estimator_status_t;
import roam.map_t;

/**
 * What the view knows of one estimator instance: its POSE_ path (decimated), its latest
 * TRAJECTORY_ (decimated), its latest MAP_, its latest STATUS_, and its last few poses for
 * matching against ground truth. Guarded by MapModel's lock.
 */
final class EstimatorTrack {
    static final int RECENT = 256;

    final String name;
    final int colourIndex;
    final DecimatedPath poses;
    double[][] trajectory;        // {xs, ys}, decimated when stored; null until one arrives
    long trajectoryUtime;
    map_t map;
    estimator_status_t status;
    long messages;
    String robot;      // a team robot's track (MapModel): the robot, else null
    String estimator;  // and its estimator
    int styleIndex;

    // A ring of the newest poses, for the error against ground truth at a matched time.
    final long[] recentUtime = new long[RECENT];
    final double[] recentX = new double[RECENT];
    final double[] recentY = new double[RECENT];
    int recentCount;
    int recentNext;

    EstimatorTrack(String name, int colourIndex, int pathCap) {
        this.name = name;
        this.colourIndex = colourIndex;
        this.poses = new DecimatedPath(pathCap);
    }

    void addPose(long utime, double x, double y) {
        poses.add(utime, x, y);
        if (!Double.isFinite(x) || !Double.isFinite(y)) return;
        recentUtime[recentNext] = utime;
        recentX[recentNext] = x;
        recentY[recentNext] = y;
        recentNext = (recentNext + 1) % RECENT;
        recentCount = Math.min(recentCount + 1, RECENT);
    }

    void setTrajectory(long utime, int n, double[] x, double[] y, int cap) {
        // Every step-th pose and the last: at most cap points (step = ceil((n - 1) / (cap - 1))).
        final int step = n <= cap ? 1 : (n - 1 + cap - 2) / (cap - 1);
        final int kept = n == 0 ? 0 : (n - 1) / step + 1 + ((n - 1) % step != 0 ? 1 : 0);
        final double[] xs = new double[kept];
        final double[] ys = new double[kept];
        int k = 0;
        for (int i = 0; i < n; i += step) {
            xs[k] = x[i];
            ys[k] = y[i];
            ++k;
        }
        if (k < kept) {  // always end at the path's last pose
            xs[k] = x[n - 1];
            ys[k] = y[n - 1];
        }
        trajectory = new double[][] {xs, ys};
        trajectoryUtime = utime;
    }
}
