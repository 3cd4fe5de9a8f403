package roam.spy;

import java.util.ArrayList;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;
import java.util.TreeMap;
import roam.beacon_t;
import roam.estimator_status_t;
import roam.map_t;
import roam.pose_t;
import roam.trajectory_t;

/**
 * Everything the map view draws, filled by BusListener's decoder thread and read by the Swing
 * thread through snapshot(). One lock; both sides hold it only to copy (the decoder: one message;
 * the painter: capped arrays), never while decoding or drawing.
 *
 * A team (GROUND_TRUTH_<R> / INITIAL_POSE_<R> on the bus) is drawn one colour per robot (the
 * robots in name order, as roam-plot colours them) and one line style per estimator: a track
 * whose channel ends in _<R> for a known robot R is that robot's (a one-robot plugin's instance
 * NAME_<R>, or a team plugin's TRAJECTORY_<NAME>_<R>), its style its estimator's (NAME) order of
 * appearance. Single-robot tracks keep their own colour and a solid line.
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
    private final Map<String, Robot> robots = new TreeMap<>();  // a team's, by name
    private final Map<String, Integer> styles = new LinkedHashMap<>();  // a team's estimators

    /** A team robot's ground truth and start. */
    private static final class Robot {
        final GroundTruth truth = new GroundTruth();
        final DecimatedPath path = new DecimatedPath(PATH_CAP);
        double[] start;
    }
    private long version;

    void onPose(String channel, pose_t p) {
        synchronized (lock) {
            if (channel.equals("GROUND_TRUTH")) {
                truth.add(p.utime, p.x, p.y);
                truthPath.add(p.utime, p.x, p.y);
            } else if (channel.equals("INITIAL_POSE")) {
                start = new double[] {p.x, p.y};
            } else if (channel.startsWith("GROUND_TRUTH_")) {
                final Robot r = robot(channel.substring("GROUND_TRUTH_".length()));
                r.truth.add(p.utime, p.x, p.y);
                r.path.add(p.utime, p.x, p.y);
            } else if (channel.startsWith("INITIAL_POSE_")) {
                robot(channel.substring("INITIAL_POSE_".length())).start = new double[] {p.x, p.y};
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
            robots.clear();
            styles.clear();
            ++version;
        }
    }

    long version() {
        synchronized (lock) {
            return version;
        }
    }

    private Robot robot(String name) {
        return robots.computeIfAbsent(name, n -> new Robot());
    }

    // The known robot whose "_<R>" ends text after at least one character, the longest; or null.
    private String robotOf(String text) {
        String best = null;
        for (String r : robots.keySet()) {
            final String tail = "_" + r;
            if (text.length() > tail.length() && text.endsWith(tail) && (best == null || r.length() > best.length()))
                best = r;
        }
        return best;
    }

    // Messages name their estimator; a message without one goes by its channel's suffix. In a
    // team, a team plugin's robot R path (TRAJECTORY_<NAME>_<R>, estimator NAME) is track NAME_<R>.
    private EstimatorTrack track(String estimator, String channel) {
        String name = estimator;
        if (name == null || name.isEmpty()) {
            final int cut = channel.indexOf('_');
            name = (cut >= 0 ? channel.substring(cut + 1) : channel).toLowerCase();
        }
        String robot = null, base = name;
        if (!robots.isEmpty()) {
            robot = robotOf(name);
            if (robot != null) {
                base = name.substring(0, name.length() - robot.length() - 1);
            } else {
                robot = robotOf(channel);
                if (robot != null) name = name + "_" + robot;
            }
        }
        EstimatorTrack t = tracks.get(name);
        if (t == null) {
            t = new EstimatorTrack(name, tracks.size(), PATH_CAP);
            t.robot = robot;
            if (robot != null) {
                if (!styles.containsKey(base)) styles.put(base, styles.size());
                t.styleIndex = styles.get(base);
                t.estimator = base;
            }
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
        String robot;            // a team robot's track: the robot, else null
        String estimator;        // a team robot's track: its estimator (the name without _<R>)
        int styleIndex;          // a team robot's track: its estimator's line style (MapPainter.dash)
    }

    /** A team robot as drawn. */
    static final class RobotTruth {
        String name;
        int colourIndex;         // its place among the robots in name order
        double[][] path;         // {xs, ys, utimes} or null
        double[] start;
    }

    /** A consistent copy of everything drawn, taken under the lock. */
    static final class Snapshot {
        long version;
        double[][] truthPath;    // {xs, ys, utimes}
        long truthLastUtime;
        double[] start;
        List<Beacon> beacons = new ArrayList<>();
        List<Track> tracks = new ArrayList<>();
        List<RobotTruth> robots = new ArrayList<>();  // a team's, in name order; empty for one robot
        List<String> estimators = new ArrayList<>();  // a team's estimators, in style order
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
            int i = 0;
            for (Map.Entry<String, Robot> e : robots.entrySet()) {
                final RobotTruth r = new RobotTruth();
                r.name = e.getKey();
                r.colourIndex = i++;
                final Robot robot = e.getValue();
                r.path = robot.path.isEmpty() ? null : robot.path.copyPolyline();
                if (robot.start != null) r.start = robot.start.clone();
                else if (robot.truth.size() > 0) r.start = robot.truth.at(robot.truth.firstUtime());
                s.robots.add(r);
            }
            s.estimators.addAll(styles.keySet());
            for (EstimatorTrack t : tracks.values()) s.tracks.add(copy(t));
        }
        return s;
    }

    private Track copy(EstimatorTrack t) {
        final Track c = new Track();
        c.name = t.name;
        c.colourIndex = t.colourIndex;
        GroundTruth truth = this.truth;
        if (t.robot != null) {
            c.robot = t.robot;
            c.estimator = t.estimator;
            c.styleIndex = t.styleIndex;
            c.colourIndex = new ArrayList<>(robots.keySet()).indexOf(t.robot);
            truth = robots.get(t.robot).truth;
        }
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
