package roam.spy;

import java.util.ArrayList;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;
import roam.beacon_t;
import roam.estimator_status_t;
import roam.map_t;
import roam.pose_t;
import roam.trajectory_t;

/**
 * Everything the map view draws, filled by BusListener's decoder thread and read by the Swing
 * thread through snapshot(). One lock; both sides hold it only to copy (the decoder: one message;
 * the painter: capped arrays), never while decoding or drawing.
 */
final class MapModel {
    /** Points kept per drawn path (POSE_ paths, ground truth, each TRAJECTORY_). */
    static final int PATH_CAP = 4000;

    private final Object lock = new Object();
    private final Map<String, EstimatorTrack> tracks = new LinkedHashMap<>();  // order of appearance
    private final GroundTruth truth = new GroundTruth();
    private final DecimatedPath truthPath = new DecimatedPath(PATH_CAP);
    private map_t surveyed;
    private double[] start;  // INITIAL_POSE {x, y}
    private long version;

    void onPose(String channel, pose_t p) {
        synchronized (lock) {
            if (channel.equals("GROUND_TRUTH")) {
                truth.add(p.utime, p.x, p.y);
                truthPath.add(p.utime, p.x, p.y);
            } else if (channel.equals("INITIAL_POSE")) {
                start = new double[] {p.x, p.y};
            } else {
                track(p.estimator, channel).addPose(p.utime, p.x, p.y);
            }
            ++version;
        }
    }

    void onMap(String channel, map_t m) {
        synchronized (lock) {
            if (channel.equals("BEACONS")) surveyed = m;
            else track(m.estimator, channel).map = m;
            ++version;
        }
    }

    void onTrajectory(String channel, trajectory_t t) {
        synchronized (lock) {
            track(t.estimator, channel).setTrajectory(t.utime, t.num_poses, t.x, t.y, PATH_CAP);
            ++version;
        }
    }

    void onStatus(String channel, estimator_status_t s) {
        synchronized (lock) {
            track(s.estimator, channel).status = s;
            ++version;
        }
    }

    void clear() {
        synchronized (lock) {
            tracks.clear();
            truth.clear();
            truthPath.clear();
            surveyed = null;
            start = null;
            ++version;
        }
    }

    long version() {
        synchronized (lock) {
            return version;
        }
    }

    // Messages name their estimator; a message without one goes by its channel's suffix.
    private EstimatorTrack track(String estimator, String channel) {
        String name = estimator;
        if (name == null || name.isEmpty()) {
            final int cut = channel.indexOf('_');
            name = (cut >= 0 ? channel.substring(cut + 1) : channel).toLowerCase();
        }
        EstimatorTrack t = tracks.get(name);
        if (t == null) {
            t = new EstimatorTrack(name, tracks.size(), PATH_CAP);
            tracks.put(name, t);
        }
        ++t.messages;
        return t;
    }

    /** A beacon as drawn: position and the 2x2 covariance (NaN where unknown). */
    static final class Beacon {
        final int id;
        final double x, y, cxx, cxy, cyy;

        Beacon(beacon_t b) {
            id = b.id;
            x = b.x;
            y = b.y;
            cxx = b.covariance[0];
            cxy = b.covariance[1];
            cyy = b.covariance[3];
        }
    }

    /** One estimator as drawn and read out. */
    static final class Track {
        String name;
        int colourIndex;
        double[][] path;         // POSE_ path {xs, ys, utimes}
        double[][] trajectory;   // latest TRAJECTORY_ or null
        List<Beacon> map = new ArrayList<>();
        estimator_status_t status;
        boolean hasPose;
        long lastUtime;
        double lastX, lastY;
        double errorM = Double.NaN;   // against ground truth at errorUtime
        long errorUtime;
        long messages;
    }

    /** A consistent copy of everything drawn, taken under the lock. */
    static final class Snapshot {
        long version;
        double[][] truthPath;    // {xs, ys, utimes}
        long truthLastUtime;
        double[] start;
        List<Beacon> beacons = new ArrayList<>();
        List<Track> tracks = new ArrayList<>();
    }

    Snapshot snapshot() {
        final Snapshot s = new Snapshot();
        synchronized (lock) {
            s.version = version;
            s.truthPath = truthPath.isEmpty() ? null : truthPath.copyPolyline();
            s.truthLastUtime = truth.size() > 0 ? truth.lastUtime() : 0;
            if (start != null) s.start = start.clone();
            else if (truth.size() > 0) s.start = truth.at(truth.firstUtime());
            if (surveyed != null)
                for (beacon_t b : surveyed.beacons) s.beacons.add(new Beacon(b));
            for (EstimatorTrack t : tracks.values()) s.tracks.add(copy(t));
        }
        return s;
    }

    private Track copy(EstimatorTrack t) {
        final Track c = new Track();
        c.name = t.name;
        c.colourIndex = t.colourIndex;
        c.path = t.poses.copyPolyline();
        c.trajectory = t.trajectory;  // replaced whole, never changed in place
        if (t.map != null)
            for (beacon_t b : t.map.beacons) c.map.add(new Beacon(b));
        c.status = t.status;          // likewise
        c.messages = t.messages;
        c.hasPose = !t.poses.isEmpty();
        if (c.hasPose) {
            c.lastUtime = t.poses.lastUtime();
            c.lastX = t.poses.lastX();
            c.lastY = t.poses.lastY();
        }
        // The error now: the newest pose whose time ground truth covers (ground truth may lag
        // or lead the estimates by a message or two on the bus).
        for (int k = 1; k <= t.recentCount; ++k) {
            final int i = Math.floorMod(t.recentNext - k, EstimatorTrack.RECENT);
            if (!truth.covers(t.recentUtime[i])) continue;
            final double[] g = truth.at(t.recentUtime[i]);
            c.errorM = Math.hypot(t.recentX[i] - g[0], t.recentY[i] - g[1]);
            c.errorUtime = t.recentUtime[i];
            break;
        }
        return c;
    }
}
