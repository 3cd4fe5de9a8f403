package roam.spy;

import java.util.Collections;
import roam.estimator_status_t;
import roam.pose_t;
import roam.trajectory_t;

/**
 * Unit tests of the map view's pieces that need no display: path decimation, ground-truth
 * matching, the 2-sigma ellipse, the world-to-pixel transform and its fits, the model's naming,
 * colours and error, and the readout's numbers. Expected values are worked out in comments.
 * Run by ctest (spy_map_view_unit); exit 1 on the first failure.
 */
public final class MapViewUnitTest {
    private static final double kTolerance = 1e-9;
    private static int checks;

    private MapViewUnitTest() {}

    public static void main(String[] args) {
        decimatedPathStaysUnderItsCapAndEvenlySpread();
        decimatedPathEndsAtTheNewestPoint();
        trajectoryIsDecimatedToItsCapAndKeepsItsEnds();
        groundTruthInterpolatesLinearly();
        twoSigmaEllipseMatchesItsEigenvalues();
        transformFitsABoxAndInvertsItself();
        stickyFitKeepsAPictureThatStillShowsEverything();
        modelNamesColoursAndErrors();
        teamTracksTakeTheirRobotsColourAndTheirEstimatorsStyle();
        readoutNumbers();
        eachEstimatorsMapIsDrawnInItsOwnColour();
        System.out.println("PASSED: " + checks + " checks");
    }

    static void decimatedPathStaysUnderItsCapAndEvenlySpread() {
        final DecimatedPath path = new DecimatedPath(100);
        for (int i = 0; i < 10000; ++i) path.add(i, i, 2 * i);
        // 10,000 points into 100: the stride doubles each time the path fills, 1 -> 2 -> ... -> 128
        // (10,000 / 128 = 78 points; at stride 64 it would need 156 > 100).
        check("size under the cap", path.size() <= 100 && path.size() >= 50);
        final double[][] p = path.copyPolyline();
        check("first point kept", p[2][0] == 0);
        final double stride = p[2][1] - p[2][0];
        check("stride 128", stride == 128);
        for (int i = 1; i < path.size(); ++i) check("even spacing", p[2][i] - p[2][i - 1] == stride);
        for (int i = 0; i < p[0].length; ++i) check("x, y follow t", p[0][i] == p[2][i] && p[1][i] == 2 * p[2][i]);
    }

    static void decimatedPathEndsAtTheNewestPoint() {
        final DecimatedPath path = new DecimatedPath(10);
        for (int i = 0; i < 25; ++i) path.add(i, i, 0);
        path.add(25, Double.NaN, 0);  // not finite: ignored
        final double[][] p = path.copyPolyline();
        check("tail is the newest finite point", p[2][p[2].length - 1] == 24 && path.lastX() == 24);
    }

    static void trajectoryIsDecimatedToItsCapAndKeepsItsEnds() {
        final EstimatorTrack track = new EstimatorTrack("t", 0, 100);
        final double[] x = new double[11], y = new double[11];
        for (int i = 0; i < 11; ++i) x[i] = i;
        // 11 poses into 4: step ceil(10 / 3) = 4, poses 0, 4, 8 and the last, 10.
        track.setTrajectory(0, 11, x, y, 4);
        checkArray("11 into 4", track.trajectory[0], new double[] {0, 4, 8, 10});
        // 10 poses into 4: step 3, poses 0, 3, 6, 9 (9 is the last already).
        track.setTrajectory(0, 10, x, y, 4);
        checkArray("10 into 4", track.trajectory[0], new double[] {0, 3, 6, 9});
        track.setTrajectory(0, 3, x, y, 4);
        checkArray("3 fit", track.trajectory[0], new double[] {0, 1, 2});
    }

    static void groundTruthInterpolatesLinearly() {
        final GroundTruth truth = new GroundTruth();
        truth.add(0, 0, 0);
        truth.add(10_000_000, 10, 20);
        truth.add(5_000_000, 99, 99);  // out of order: dropped
        // Halfway in time, halfway in space: (5, 10).
        final double[] mid = truth.at(5_000_000);
        check("x at 5 s", Math.abs(mid[0] - 5) < kTolerance);
        check("y at 5 s", Math.abs(mid[1] - 10) < kTolerance);
        check("covers its ends", truth.covers(0) && truth.covers(10_000_000));
        check("not beyond", !truth.covers(10_000_001) && !truth.covers(-1));
    }

    static void twoSigmaEllipseMatchesItsEigenvalues() {
        // diag(4, 1): sigmas 2 and 1, so the 2-sigma half axes are 4 and 2, along x.
        double[] e = MapPainter.twoSigmaEllipse(4, 0, 1);
        check("diag major", Math.abs(e[0] - 4) < kTolerance);
        check("diag minor", Math.abs(e[1] - 2) < kTolerance);
        check("diag angle", Math.abs(e[2]) < kTolerance);
        // [[2, 1], [1, 2]]: eigenvalues 3 (along (1, 1)) and 1: half axes 2 sqrt 3 and 2, at 45 degrees.
        e = MapPainter.twoSigmaEllipse(2, 1, 2);
        check("tilted major", Math.abs(e[0] - 2 * Math.sqrt(3)) < kTolerance);
        check("tilted minor", Math.abs(e[1] - 2) < kTolerance);
        check("tilted angle", Math.abs(e[2] - Math.PI / 4) < kTolerance);
        // [[1, 2], [2, 1]] has eigenvalues 3 and -1: not a covariance.
        check("indefinite", MapPainter.twoSigmaEllipse(1, 2, 1) == null);
        check("unknown", MapPainter.twoSigmaEllipse(Double.NaN, 0, 1) == null);
    }

    static void transformFitsABoxAndInvertsItself() {
        // [0, 100] x [0, 50] into 220 x 120 with a 10 px margin: scale min(200 / 100, 100 / 50) = 2
        // about (50, 25); x = 0 -> 110 + (0 - 50) 2 = 10; y = 50 -> 60 - (50 - 25) 2 = 10 (y down).
        final WorldTransform t = WorldTransform.fit(0, 100, 0, 50, 220, 120, 10);
        check("scale", Math.abs(t.scalePxPerM - 2) < kTolerance);
        check("left edge", Math.abs(t.px(0) - 10) < kTolerance);
        check("top edge", Math.abs(t.py(50) - 10) < kTolerance);
        check("round trip x", Math.abs(t.worldX(t.px(37.5)) - 37.5) < kTolerance);
        check("round trip y", Math.abs(t.worldY(t.py(-12.25)) + 12.25) < kTolerance);
    }

    static void stickyFitKeepsAPictureThatStillShowsEverything() {
        final MapModel model = new MapModel();
        for (int i = 0; i <= 100; ++i) model.onPose("GROUND_TRUTH", pose(i * 1_000_000L, "", i, i % 2));
        final WorldTransform first = MapPainter.fittedSticky(null, model.snapshot(), Collections.<String>emptySet(), 400, 300);
        // A little more path inside what is shown: the picture stays as it is.
        model.onPose("GROUND_TRUTH", pose(101_000_000L, "", 99, 0.5));
        check("kept", MapPainter.fittedSticky(first, model.snapshot(), Collections.<String>emptySet(), 400, 300) == first);
        // Path far outside: a new fit.
        model.onPose("GROUND_TRUTH", pose(102_000_000L, "", 300, 0));
        check("refit", MapPainter.fittedSticky(first, model.snapshot(), Collections.<String>emptySet(), 400, 300) != first);
        check("resized", MapPainter.fittedSticky(first, model.snapshot(), Collections.<String>emptySet(), 500, 300) != first);
    }

    static void modelNamesColoursAndErrors() {
        final MapModel model = new MapModel();
        // Ground truth along x at 1 m/s for 10 s.
        for (int i = 0; i <= 10; ++i) model.onPose("GROUND_TRUTH", pose(i * 1_000_000L, "", i, 0));
        model.onPose("POSE_B", pose(5_500_000L, "b", 5.5, 3));   // 3 m to the side of (5.5, 0)
        model.onPose("POSE_A", pose(20_000_000L, "", 20, 0));    // no name: from the channel; past the truth
        final estimator_status_t status = new estimator_status_t();
        status.estimator = "b";
        status.keys = new String[0];
        status.values = new double[0];
        model.onStatus("STATUS_B", status);
        final MapModel.Snapshot s = model.snapshot();
        check("two estimators", s.tracks.size() == 2);
        check("order of appearance", s.tracks.get(0).name.equals("b") && s.tracks.get(0).colourIndex == 0);
        check("named by channel", s.tracks.get(1).name.equals("a") && s.tracks.get(1).colourIndex == 1);
        check("error 3 m", Math.abs(s.tracks.get(0).errorM - 3) < kTolerance);
        check("no truth at its time", Double.isNaN(s.tracks.get(1).errorM));
        check("status kept", s.tracks.get(0).status == status);
        check("roam-plot's first colour", Palette.hex(Palette.series(0)).equals("#0072B2"));
        check("roam-plot's second colour", Palette.hex(Palette.series(1)).equals("#D55E00"));
        check("palette wraps at 8", Palette.series(8).equals(Palette.series(0)));
    }

    static void teamTracksTakeTheirRobotsColourAndTheirEstimatorsStyle() {
        final MapModel model = new MapModel();
        // Robots B then A appear; colours go by name (A first), as roam-plot's.
        for (int i = 0; i <= 10; ++i) {
            model.onPose("GROUND_TRUTH_B", pose(i * 1_000_000L, "", i, 10));
            model.onPose("GROUND_TRUTH_A", pose(i * 1_000_000L, "", i, 0));
        }
        model.onPose("POSE_DR_B", pose(5_000_000L, "dr_B", 5, 12));  // a one-robot plugin's instance: 2 m off
        model.onPose("POSE_DR_A", pose(5_000_000L, "dr_A", 5, 1));   // 1 m off
        final trajectory_t t = new trajectory_t();
        t.estimator = "team";                                       // a team plugin's path for A
        t.num_poses = 2;
        t.utimes = new long[] {0, 1_000_000L};
        t.x = new double[] {0, 1};
        t.y = new double[] {0, 0};
        t.heading = new double[] {0, 0};
        model.onTrajectory("TRAJECTORY_TEAM_A", t);
        final MapModel.Snapshot s = model.snapshot();
        check("two robots in name order", s.robots.size() == 2 && s.robots.get(0).name.equals("A")
                                          && s.robots.get(0).colourIndex == 0 && s.robots.get(1).colourIndex == 1);
        check("robot starts from their truth", s.robots.get(1).start[1] == 10);
        check("three tracks", s.tracks.size() == 3);
        final MapModel.Track drB = s.tracks.get(0), drA = s.tracks.get(1), teamA = s.tracks.get(2);
        check("instance named as published", drB.name.equals("dr_B") && drB.robot.equals("B"));
        check("B's colour", drB.colourIndex == 1 && drA.colourIndex == 0);
        check("error against the robot's own truth", Math.abs(drB.errorM - 2) < kTolerance
                                                     && Math.abs(drA.errorM - 1) < kTolerance);
        check("team path named by its robot", teamA.name.equals("team_A") && teamA.robot.equals("A")
                                              && teamA.colourIndex == 0);
        check("styles by estimator", drA.styleIndex == 0 && drB.styleIndex == 0 && teamA.styleIndex == 1);
        check("estimators in style order", s.estimators.equals(java.util.Arrays.asList("dr", "team")));
        check("a dashed second style", MapPainter.styleName(1).equals("dashed"));
    }

    static void readoutNumbers() {
        check("count", StatusText.number(4.0).equals("4"));
        check("four digits", StatusText.number(1.06749).equals("1.067"));
        check("small", StatusText.number(0.0001234).equals("0.0001234"));
        final estimator_status_t s = new estimator_status_t();
        s.state = estimator_status_t.FAILED;
        s.last_error = "boom";
        s.last_rejection = "";
        s.keys = new String[] {"range_scale"};
        s.values = new double[] {1.0125};
        s.num_values = 1;
        check("failed", StatusText.status(s).startsWith("FAILED"));
        check("error first", StatusText.rejection(s).equals("error: boom"));
        check("diagnostics", StatusText.diagnostics(s)[0].equals("range_scale=1.013"));
    }

    private static pose_t pose(long utime, String estimator, double x, double y) {
        final pose_t p = new pose_t();
        p.utime = utime;
        p.estimator = estimator;
        p.x = x;
        p.y = y;
        return p;
    }

    /**
     * Two estimators, each with one mapped beacon and a short path: each beacon's cross is drawn
     * in its estimator's colour, not in the colour of the last path drawn.
     */
    static void eachEstimatorsMapIsDrawnInItsOwnColour() {
        final MapModel.Snapshot s = new MapModel.Snapshot();
        for (int i = 0; i < 2; ++i) {
            final MapModel.Track track = new MapModel.Track();
            track.name = "e" + i;
            track.colourIndex = i;
            track.path = new double[][] {{0, 1}, {40 * i, 40 * i}, {0, 1}};
            final roam.beacon_t b = new roam.beacon_t();
            b.id = i;
            b.x = 20 + 40 * i;  // crosses at (20, 20) and (60, 20), away from the paths
            b.y = 20;
            b.covariance = new double[] {Double.NaN, 0, 0, Double.NaN};
            track.map.add(new MapModel.Beacon(b));
            s.tracks.add(track);
        }
        final WorldTransform t = new WorldTransform(4, 40, 20, 400, 200);  // 4 px/m, centre (40, 20)
        final MapPainter.Layer layer = MapPainter.layer(null, s, Collections.emptySet(), t);
        final java.awt.image.BufferedImage image =
            new java.awt.image.BufferedImage(400, 200, java.awt.image.BufferedImage.TYPE_INT_RGB);
        final java.awt.Graphics2D g = image.createGraphics();
        MapPainter.draw(g, s, Collections.emptySet(), t, layer);
        g.dispose();
        // The darkest pixel around each cross (antialiased strokes blend into white at their edges)
        // is nearer its own estimator's colour than the other's.
        for (int i = 0; i < 2; ++i) {
            final int cx = (int) Math.round(t.px(20 + 40 * i)), cy = (int) Math.round(t.py(20));
            int darkest = 0xFFFFFF;
            for (int y = cy - 5; y <= cy + 5; ++y)
                for (int x = cx - 5; x <= cx + 5; ++x) {
                    final int rgb = image.getRGB(x, y) & 0xFFFFFF;
                    if (brightness(rgb) < brightness(darkest)) darkest = rgb;
                }
            final int own = Palette.series(i).getRGB() & 0xFFFFFF, other = Palette.series(1 - i).getRGB() & 0xFFFFFF;
            check("beacon cross " + i + " in its estimator's colour " + Palette.hex(Palette.series(i)) + ", got "
                      + String.format("#%06X", darkest),
                  colourDistance(darkest, own) < colourDistance(darkest, other));
        }
    }

    private static int brightness(int rgb) {
        return ((rgb >> 16) & 0xFF) + ((rgb >> 8) & 0xFF) + (rgb & 0xFF);
    }

    private static int colourDistance(int a, int b) {
        final int dr = ((a >> 16) & 0xFF) - ((b >> 16) & 0xFF), dg = ((a >> 8) & 0xFF) - ((b >> 8) & 0xFF);
        final int db = (a & 0xFF) - (b & 0xFF);
        return dr * dr + dg * dg + db * db;
    }

    private static void checkArray(String what, double[] got, double[] want) {
        check(what + ": length " + got.length, got.length == want.length);
        for (int i = 0; i < want.length; ++i) check(what + "[" + i + "]", got[i] == want[i]);
    }

    private static void check(String what, boolean ok) {
        ++checks;
        if (ok) return;
        System.out.println("FAILED: " + what);
        System.exit(1);
    }
}
