import java.awt.image.BufferedImage;
import java.io.File;
import java.io.IOException;
import java.nio.file.Files;
import java.util.ArrayList;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;
import javax.imageio.ImageIO;
import lcm.lcm.LCMDataInputStream;
import lcm.logging.Log;

/**
 * Checks a snapshot of roam's map view against the log of the same live run, pixel by pixel:
 *   java -cp lcm.jar:lcmtypes_roam.jar MapViewCheck.java SNAPSHOT.png RUN.lcmlog NAME=#RRGGBB...
 * SNAPSHOT.png.txt (written with the PNG by the view) gives the world-to-image transform:
 *   px = canvas_x + canvas_w/2 + (x - centre_x) * scale,  py = canvas_y + canvas_h/2 - (y - centre_y) * scale.
 * Expected positions come from the log (what was on the bus), not from the view:
 *  - each surveyed beacon (BEACONS): the pixel at its position is the true-beacon yellow #FFD400
 *    (the triangle is drawn around that point: 7 px above, 4.5 px below);
 *  - ground truth (GROUND_TRUTH rows up to the newest the view had): a pixel of the truth grey
 *    (#444444 at 35 % on white, about 190) within RADIUS_PX of at least MIN_FRACTION of them;
 *  - each NAME (POSE_<NAME> rows up to the view's newest): a pixel of its colour within
 *    RADIUS_PX of at least MIN_FRACTION of them; the colour is also the one the sidecar reports.
 * Points under the legend box, under the start circle or an estimator's current-position dot
 * (within MARKER_PX) or outside the canvas are not counted, nor points of a path within
 * COVERED_PX of a path drawn over it (ground truth is drawn first, then the estimators in order).
 * As a control, the same
 * checks with every expected point moved CONTROL_SHIFT_M metres must fail (at most
 * MAX_CONTROL_FRACTION hit), so a check that passes is one that could have failed.
 * Exit 0 when all pass, 1 when one fails, 2 on a usage or file error.
 */
public final class MapViewCheck {
    static final int RADIUS_PX = 2;
    static final double MIN_FRACTION = 0.9;
    static final double COVERED_PX = 3.5;  // a later-drawn path this close may hide the line beneath
    static final double MARKER_PX = 8;     // the start circle and current-position dots hide this much
    static final double MAX_CONTROL_FRACTION = 0.3;
    static final double CONTROL_SHIFT_M = 6.0;
    static final int SAMPLES = 300;
    static final double COLOUR_TOLERANCE = 60;  // RGB distance (antialiased line centres are closer)

    static BufferedImage image;
    static int canvasX, canvasY, canvasW, canvasH, legendX, legendY, legendW, legendH;
    static double scale, centreX, centreY;
    static final List<double[]> markers = new ArrayList<>();  // world positions of drawn markers

    public static void main(String[] args) throws IOException {
        if (args.length < 3) {
            System.err.println("usage: MapViewCheck SNAPSHOT.png RUN.lcmlog NAME=#RRGGBB...");
            System.exit(2);
        }
        image = ImageIO.read(new File(args[0]));
        final Map<String, String[]> side = readSidecar(args[0] + ".txt");
        final String[] canvas = side.get("canvas"), transform = side.get("transform"), legend = side.get("legend");
        canvasX = Integer.parseInt(canvas[0]); canvasY = Integer.parseInt(canvas[1]);
        canvasW = Integer.parseInt(canvas[2]); canvasH = Integer.parseInt(canvas[3]);
        scale = Double.parseDouble(transform[0]);
        centreX = Double.parseDouble(transform[1]);
        centreY = Double.parseDouble(transform[2]);
        legendX = Integer.parseInt(legend[0]); legendY = Integer.parseInt(legend[1]);
        legendW = Integer.parseInt(legend[2]); legendH = Integer.parseInt(legend[3]);
        final long truthUntil = Long.parseLong(side.get("ground_truth_last_utime")[0]);
        System.out.printf("transform: %.4f px/m about (%.2f, %.2f) m; canvas %dx%d at (%d, %d)%n", scale, centreX,
                          centreY, canvasW, canvasH, canvasX, canvasY);

        // What was on the bus, from the run's log.
        final List<double[]> beacons = new ArrayList<>(), truth = new ArrayList<>();
        final Map<String, List<double[]>> poses = new LinkedHashMap<>();
        final Map<String, String> colours = new LinkedHashMap<>();
        for (int i = 2; i < args.length; ++i) {
            final String[] kv = args[i].split("=", 2);
            colours.put(kv[0], kv[1].toUpperCase());
            poses.put("POSE_" + kv[0].toUpperCase(), new ArrayList<>());
        }
        final Log log = new Log(args[1], "r");
        try {
            for (;;) {
                final Log.Event e = log.readNext();
                final LCMDataInputStream in = new LCMDataInputStream(e.data);
                if (e.channel.equals("BEACONS")) {
                    for (roam.beacon_t b : new roam.map_t(in).beacons) beacons.add(new double[] {b.x, b.y, b.id});
                } else if (e.channel.equals("INITIAL_POSE")) {
                    final roam.pose_t p = new roam.pose_t(in);
                    markers.add(new double[] {p.x, p.y});
                } else if (e.channel.equals("GROUND_TRUTH")) {
                    final roam.pose_t p = new roam.pose_t(in);
                    if (p.utime <= truthUntil) truth.add(new double[] {p.x, p.y, p.utime});
                } else if (poses.containsKey(e.channel)) {
                    final roam.pose_t p = new roam.pose_t(in);
                    poses.get(e.channel).add(new double[] {p.x, p.y, p.utime});
                }
            }
        } catch (java.io.EOFException end) {
            log.close();
        }

        boolean ok = true;
        // Beacons: yellow at the point itself and its 4 neighbours.
        int checked = 0, hit = 0, controlHit = 0;
        for (double[] b : beacons) {
            final double px = px(b[0]), py = py(b[1]);
            if (!countable(px, py)) continue;
            ++checked;
            final double[] moved = moved(b[0], b[1]);
            final boolean yes = yellowAt(px, py), control = moved != null && yellowAt(px(moved[0]), py(moved[1]));
            System.out.printf("beacon %d at (%.2f, %.2f) m -> pixel (%.1f, %.1f): %s%n", (int) b[2], b[0], b[1], px, py,
                              yes ? "yellow" : "NOT yellow, " + describe(px, py));
            if (yes) ++hit;
            if (control) ++controlHit;
        }
        if (checked < 3 || hit < checked || controlHit > 0) {
            System.out.printf("FAILED: beacons: %d of %d drawn at their position (control: %d); need all, at least 3%n",
                              hit, checked, controlHit);
            ok = false;
        }
        final List<List<double[]>> drawnOver = new ArrayList<>();  // the estimators' paths, in drawing order
        for (Map.Entry<String, String> c : colours.entrySet()) {
            final String[] reported = side.get("estimator " + c.getKey());
            final long until = reported == null ? Long.MIN_VALUE : Long.parseLong(reported[2]);
            final List<double[]> path = new ArrayList<>();
            for (double[] p : poses.get("POSE_" + c.getKey().toUpperCase())) if (p[2] <= until) path.add(p);
            drawnOver.add(path);
            if (!path.isEmpty()) markers.add(path.get(path.size() - 1));  // its current-position dot
        }
        ok &= checkPath("ground truth", truth, MapViewCheck::truthGrey, drawnOver, truth.size());
        int estimators = 0, index = 0;
        for (Map.Entry<String, String> c : colours.entrySet()) {
            final String name = c.getKey();
            final String[] reported = side.get("estimator " + name);
            if (reported == null || !reported[0].equalsIgnoreCase(c.getValue()) || !reported[1].equals("shown")) {
                System.out.printf("FAILED: the view reports %s as %s, expected %s shown%n", name,
                                  reported == null ? "absent" : String.join(" ", reported), c.getValue());
                ok = false;
                ++index;
                continue;
            }
            final List<double[]> path = drawnOver.get(index);
            final int rgb = Integer.parseInt(c.getValue().substring(1), 16);
            ++index;
            if (checkPath(name + " " + c.getValue(), path, (x, y) -> near(x, y, rgb), drawnOver.subList(index, drawnOver.size()), SAMPLES))
                ++estimators;
            else ok = false;
        }
        if (estimators < 2) {
            System.out.println("FAILED: fewer than two estimators' paths drawn in their colours");
            ok = false;
        }
        System.out.println(ok ? "PASSED: ground truth, beacons and every estimator drawn where the log says"
                              : "FAILED: see above");
        System.exit(ok ? 0 : 1);
    }

    interface PixelTest {
        boolean test(int x, int y);
    }

    // Samples the path evenly; a sample hits when a matching pixel lies within RADIUS_PX.
    static boolean checkPath(String what, List<double[]> path, PixelTest match, List<List<double[]>> over, int samples) {
        int counted = 0, hits = 0, covered = 0, controlCounted = 0, controlHits = 0;
        final int step = Math.max(1, path.size() / samples);
        for (int i = 0; i < path.size(); i += step) {
            final double[] p = path.get(i);
            if (countable(px(p[0]), py(p[1]))) {
                if (coveredBy(px(p[0]), py(p[1]), over)) {
                    ++covered;
                } else {
                    ++counted;
                    if (anyWithin(px(p[0]), py(p[1]), match)) ++hits;
                    else if (System.getenv("MAPVIEW_DEBUG") != null)
                        System.out.printf("  miss %s at (%.1f, %.1f): %s%n", what, px(p[0]), py(p[1]), describe(px(p[0]), py(p[1])));
                }
            }
            final double[] m = moved(p[0], p[1]);
            if (m != null && !coveredBy(px(m[0]), py(m[1]), over)) {
                ++controlCounted;
                if (anyWithin(px(m[0]), py(m[1]), match)) ++controlHits;
            }
        }
        final double fraction = counted == 0 ? 0 : (double) hits / counted;
        final double control = controlCounted == 0 ? 1 : (double) controlHits / controlCounted;
        final boolean ok = counted >= 50 && fraction >= MIN_FRACTION && control <= MAX_CONTROL_FRACTION;
        System.out.printf("%s: %s: %d of %d sampled positions (of %d; %d under later paths) drawn within %d px"
                              + " (%.0f %%, need %.0f %%); moved %.0f m: %.0f %% (at most %.0f %%)%n",
                          ok ? "ok" : "FAILED", what, hits, counted, path.size(), covered, RADIUS_PX, 100 * fraction,
                          100 * MIN_FRACTION, CONTROL_SHIFT_M, 100 * control, 100 * MAX_CONTROL_FRACTION);
        return ok;
    }

    static boolean coveredBy(double px, double py, List<List<double[]>> over) {
        for (List<double[]> path : over)
            for (double[] q : path)
                if (Math.hypot(px(q[0]) - px, py(q[1]) - py) <= COVERED_PX) return true;
        return false;
    }

    // The control position of a world point: CONTROL_SHIFT_M away diagonally, in the first of the
    // four diagonal directions that stays countable (null if none does).
    static double[] moved(double x, double y) {
        final int[][] signs = {{1, 1}, {-1, -1}, {1, -1}, {-1, 1}};
        for (int[] s : signs) {
            final double mx = x + s[0] * CONTROL_SHIFT_M, my = y + s[1] * CONTROL_SHIFT_M;
            if (countable(px(mx), py(my))) return new double[] {mx, my};
        }
        return null;
    }

    static double px(double x) {
        return canvasX + canvasW / 2.0 + (x - centreX) * scale;
    }

    static double py(double y) {
        return canvasY + canvasH / 2.0 - (y - centreY) * scale;
    }

    // Inside the canvas (a margin for the search radius) and clear of the legend box.
    static boolean countable(double px, double py) {
        final int m = RADIUS_PX + 8;
        if (px < canvasX + m || py < canvasY + m || px >= canvasX + canvasW - m || py >= canvasY + canvasH - m) return false;
        for (double[] k : markers)
            if (Math.hypot(px(k[0]) - px, py(k[1]) - py) <= MARKER_PX) return false;
        return !(px >= legendX - m && px < legendX + legendW + m && py >= legendY - m && py < legendY + legendH + m);
    }

    static boolean anyWithin(double px, double py, PixelTest match) {
        final int cx = (int) Math.round(px), cy = (int) Math.round(py);
        for (int dy = -RADIUS_PX; dy <= RADIUS_PX; ++dy)
            for (int dx = -RADIUS_PX; dx <= RADIUS_PX; ++dx)
                if (dx * dx + dy * dy <= RADIUS_PX * RADIUS_PX && match.test(cx + dx, cy + dy)) return true;
        return false;
    }

    static boolean near(int x, int y, int rgb) {
        final int p = image.getRGB(x, y);
        final int dr = ((p >> 16) & 255) - ((rgb >> 16) & 255), dg = ((p >> 8) & 255) - ((rgb >> 8) & 255),
                  db = (p & 255) - (rgb & 255);
        return Math.sqrt(dr * dr + dg * dg + db * db) <= COLOUR_TOLERANCE;
    }

    // #444444 at 35 % on white is about 190; where the path crosses itself, darker.
    static boolean truthGrey(int x, int y) {
        final int p = image.getRGB(x, y), r = (p >> 16) & 255, g = (p >> 8) & 255, b = p & 255;
        return Math.abs(r - g) <= 8 && Math.abs(g - b) <= 8 && r >= 120 && r <= 205;
    }

    static boolean yellowAt(double px, double py) {
        final int x = (int) Math.round(px), y = (int) Math.round(py);
        final int[][] around = {{0, 0}, {1, 0}, {-1, 0}, {0, 1}, {0, -1}};
        for (int[] d : around) if (!near(x + d[0], y + d[1], 0xFFD400)) return false;
        return true;
    }

    static String describe(double px, double py) {
        return String.format("#%06X", image.getRGB((int) Math.round(px), (int) Math.round(py)) & 0xFFFFFF);
    }

    // "key values..." lines; an estimator line is keyed "estimator NAME".
    static Map<String, String[]> readSidecar(String path) throws IOException {
        final Map<String, String[]> m = new LinkedHashMap<>();
        for (String line : Files.readAllLines(new File(path).toPath())) {
            if (line.startsWith("#") || line.trim().isEmpty()) continue;
            final String[] f = line.trim().split("\\s+");
            if (f[0].equals("estimator")) m.put("estimator " + f[1], java.util.Arrays.copyOfRange(f, 2, f.length));
            else m.put(f[0], java.util.Arrays.copyOfRange(f, 1, f.length));
        }
        return m;
    }
}
