package roam.spy;

import java.awt.BasicStroke;
import java.awt.Color;
import java.awt.Font;
import java.awt.Graphics2D;
import java.awt.Rectangle;
import java.awt.RenderingHints;
import java.awt.Stroke;
import java.awt.geom.AffineTransform;
import java.awt.geom.Ellipse2D;
import java.awt.geom.Line2D;
import java.awt.geom.Path2D;
import java.awt.image.BufferedImage;
import java.util.HashMap;
import java.util.HashSet;
import java.util.Map;
import java.util.Set;

/**
 * Draws the map, to scale: ground truth, each shown estimator's POSE_ path (solid), latest
 * TRAJECTORY_ (a pale band beneath) and MAP_ (crosses with 2-sigma ellipses), its current position, surveyed
 * beacons, the start, a legend of marks and a scale bar. Styles follow roam-plot
 * (plot_marks.cpp). Polylines skip points less than a pixel from the last one drawn. Called off the Swing thread (MapCanvas).
 * A team (MapModel) is drawn as roam-plot draws one: each robot's ground truth a wide pale band
 * in its colour, each estimator's path for it a line in that colour and the estimator's style
 * (solid, dashed, dotted, dash-dot), and a second legend of robots and styles.
 */
final class MapPainter {
    private static final int MARGIN_PX = 24;
    private static final double MIN_STEP_PX = 1.0;
    private static final Font FONT = new Font(Font.SANS_SERIF, Font.PLAIN, 11);
    private static final Stroke TRUTH = new BasicStroke(4f, BasicStroke.CAP_ROUND, BasicStroke.JOIN_ROUND);
    private static final Stroke PATH = new BasicStroke(2f, BasicStroke.CAP_ROUND, BasicStroke.JOIN_ROUND);
    // The latest TRAJECTORY_: a pale band under the POSE_ path (a dashed line, as in roam-plot,
    // costs several times more to draw on every frame).
    private static final Stroke TRAJECTORY = new BasicStroke(4f, BasicStroke.CAP_ROUND, BasicStroke.JOIN_ROUND);
    private static final Stroke ELLIPSE = new BasicStroke(1f, BasicStroke.CAP_BUTT, BasicStroke.JOIN_ROUND, 10f,
                                                          new float[] {3f, 2f}, 0f);
    private static final Stroke CROSS = new BasicStroke(2.4f);
    private static final Color GRID = new Color(0xECECEC);
    // A team's (team_figures.cpp): a robot's ground truth, and an estimator's path per style.
    private static final Stroke TEAM_TRUTH = new BasicStroke(6f, BasicStroke.CAP_ROUND, BasicStroke.JOIN_ROUND);
    private static final float[][] DASHES = {null, {7f, 4f}, {1.5f, 3f}, {9f, 3f, 1.5f, 3f}};
    private static final String[] STYLE_NAMES = {"solid", "dashed", "dotted", "dash-dot"};
    private static final Stroke[] TEAM_PATHS = new Stroke[DASHES.length];

    static {
        for (int i = 0; i < DASHES.length; ++i)
            TEAM_PATHS[i] = DASHES[i] == null ? PATH
                : new BasicStroke(2f, BasicStroke.CAP_ROUND, BasicStroke.JOIN_ROUND, 10f, DASHES[i], 0f);
    }

    /** A team estimator's line style (index: its order of appearance), as roam-plot's teamDash. */
    static Stroke teamPath(int style) {
        return TEAM_PATHS[Math.floorMod(style, TEAM_PATHS.length)];
    }

    static String styleName(int style) {
        return STYLE_NAMES[Math.floorMod(style, STYLE_NAMES.length)];
    }

    /** A team robot's ground truth: its colour at 25 % opacity (team_figures.cpp). */
    static Color teamTruth(int colourIndex) {
        final Color c = Palette.series(colourIndex);
        return new Color(c.getRed(), c.getGreen(), c.getBlue(), 64);
    }

    private static Stroke pathStroke(MapModel.Track track) {
        return track.robot == null ? PATH : teamPath(track.styleIndex);
    }

    private static void drawTeamTruth(Graphics2D g, WorldTransform t, MapModel.Snapshot s) {
        g.setStroke(TEAM_TRUTH);
        for (MapModel.RobotTruth r : s.robots) {
            if (r.path == null) continue;
            g.setColor(teamTruth(r.colourIndex));
            drawPolyline(g, t, r.path, 0);
        }
    }

    private MapPainter() {}

    /** Rebuild the layer at most this often for new trajectories or long tails. */
    static final long REBUILD_NS = 1_000_000_000L;
    /** A path tail longer than this (points) asks for a rebuild. */
    static final int TAIL_POINTS = 200;

    /**
     * The picture's slow part, drawn into an image once and copied into each frame: the grid,
     * ground truth, every shown trajectory and every shown POSE_ path up to the times noted. A
     * frame adds the paths' newer points (the "tails") and everything small on top. Rebuilt at
     * once when the transform, the size or the shown set changes, and at most every REBUILD_NS
     * when a trajectory was replaced or a tail grew past TAIL_POINTS, so a frame of sixteen
     * Plaza-length paths costs a copy and a few hundred segments, not ~70,000 segments.
     */
    static final class Layer {
        final BufferedImage image;
        final WorldTransform transform;
        final Set<String> hidden;
        final double truthUntil;
        final Map<String, Double> pathUntil = new HashMap<>();
        final Map<String, double[][]> trajectories = new HashMap<>();
        final Map<String, Double> robotTruthUntil = new HashMap<>();  // a team's
        final long builtNs = System.nanoTime();

        Layer(BufferedImage image, WorldTransform transform, Set<String> hidden, double truthUntil) {
            this.image = image;
            this.transform = transform;
            this.hidden = hidden;
            this.truthUntil = truthUntil;
        }

        boolean sameView(WorldTransform t, Set<String> h) {
            return t.scalePxPerM == transform.scalePxPerM && t.centreXm == transform.centreXm
                && t.centreYm == transform.centreYm && t.widthPx == transform.widthPx
                && t.heightPx == transform.heightPx && h.equals(hidden);
        }

        boolean outdated(MapModel.Snapshot s) {
            if (s.truthPath != null && tailStart(s.truthPath, truthUntil) < s.truthPath[0].length - TAIL_POINTS) return true;
            for (MapModel.RobotTruth r : s.robots) {
                final Double until = robotTruthUntil.get(r.name);
                if (r.path != null && (until == null || tailStart(r.path, until) < r.path[0].length - TAIL_POINTS)) return true;
            }
            for (MapModel.Track track : s.tracks) {
                if (hidden.contains(track.name)) continue;
                final Double until = pathUntil.get(track.name);
                if (until == null || track.trajectory != trajectories.get(track.name)) return true;
                if (tailStart(track.path, until) < track.path[0].length - TAIL_POINTS) return true;
            }
            return false;
        }
    }

    /** The layer to draw s with: `old` while it will do, else a new one. */
    static Layer layer(Layer old, MapModel.Snapshot s, Set<String> hidden, WorldTransform t) {
        if (old != null && old.sameView(t, hidden)
            && (System.nanoTime() - old.builtNs < REBUILD_NS || !old.outdated(s)))
            return old;
        final BufferedImage image = new BufferedImage(t.widthPx, t.heightPx, BufferedImage.TYPE_INT_RGB);
        final Graphics2D g = image.createGraphics();
        try {
            hints(g);
            g.setColor(Color.WHITE);
            g.fillRect(0, 0, t.widthPx, t.heightPx);
            drawGrid(g, t);
            final double truthUntil = s.truthPath == null ? Double.NEGATIVE_INFINITY : last(s.truthPath);
            final Layer layer = new Layer(image, t, new HashSet<>(hidden), truthUntil);
            if (s.truthPath != null) {
                g.setColor(Palette.TRUTH);
                g.setStroke(TRUTH);
                drawPolyline(g, t, s.truthPath, 0);
            }
            drawTeamTruth(g, t, s);
            for (MapModel.RobotTruth r : s.robots)
                if (r.path != null) layer.robotTruthUntil.put(r.name, last(r.path));
            for (MapModel.Track track : s.tracks) {
                if (hidden.contains(track.name)) continue;
                layer.trajectories.put(track.name, track.trajectory);
                if (track.trajectory == null) continue;
                // A team robot's trajectory is often its estimator's only path (a team plugin
                // publishes no POSE_): drawn as its path is, not as a band like the ground truth's.
                final boolean team = track.robot != null;
                g.setColor(team ? Palette.series(track.colourIndex) : pale(Palette.series(track.colourIndex)));
                g.setStroke(team ? teamPath(track.styleIndex) : TRAJECTORY);
                drawPolyline(g, t, track.trajectory, 0);
            }
            for (MapModel.Track track : s.tracks) {
                if (hidden.contains(track.name)) continue;
                layer.pathUntil.put(track.name, last(track.path));
                g.setStroke(pathStroke(track));
                g.setColor(Palette.series(track.colourIndex));
                drawPolyline(g, t, track.path, 0);
            }
            return layer;
        } finally {
            g.dispose();
        }
    }

    /** Draws a frame: the layer, the newer points, maps, markers, legend. Returns the legend box. */
    static Rectangle draw(Graphics2D g, MapModel.Snapshot s, Set<String> hidden, WorldTransform t, Layer layer) {
        g.drawImage(layer.image, 0, 0, null);
        hints(g);
        if (s.truthPath != null) {
            g.setColor(Palette.TRUTH);
            g.setStroke(TRUTH);
            drawPolyline(g, t, s.truthPath, tailStart(s.truthPath, layer.truthUntil));
        }
        g.setStroke(TEAM_TRUTH);
        for (MapModel.RobotTruth r : s.robots) {
            if (r.path == null) continue;
            final Double until = layer.robotTruthUntil.get(r.name);
            g.setColor(teamTruth(r.colourIndex));
            drawPolyline(g, t, r.path, until == null ? 0 : tailStart(r.path, until));
        }
        g.setStroke(PATH);
        for (MapModel.Track track : s.tracks) {
            if (hidden.contains(track.name)) continue;
            final Double until = layer.pathUntil.get(track.name);
            g.setStroke(pathStroke(track));
            g.setColor(Palette.series(track.colourIndex));
            drawPolyline(g, t, track.path, until == null ? 0 : tailStart(track.path, until));
        }
        for (MapModel.Track track : s.tracks) {
            if (!hidden.contains(track.name)) drawMap(g, t, track, Palette.series(track.colourIndex));
        }
        for (MapModel.Track track : s.tracks) {  // current positions above every path
            if (hidden.contains(track.name) || !track.hasPose) continue;
            final double x = t.px(track.lastX), y = t.py(track.lastY);
            g.setColor(Palette.series(track.colourIndex));
            g.fill(new Ellipse2D.Double(x - 4.5, y - 4.5, 9, 9));
            g.setColor(Color.WHITE);
            g.setStroke(new BasicStroke(1.2f));
            g.draw(new Ellipse2D.Double(x - 4.5, y - 4.5, 9, 9));
        }
        if (s.start != null) drawStart(g, t.px(s.start[0]), t.py(s.start[1]));
        for (MapModel.RobotTruth r : s.robots)
            if (r.start != null) drawStart(g, t.px(r.start[0]), t.py(r.start[1]));
        g.setFont(FONT);
        for (MapModel.Beacon b : s.beacons) {
            final double x = t.px(b.x), y = t.py(b.y);
            drawTrueBeacon(g, x, y);
            g.setColor(Palette.OUTLINE);
            g.drawString(Integer.toString(b.id), (float) (x + 8), (float) (y - 6));
        }
        final Rectangle legend = drawLegend(g);
        if (!s.robots.isEmpty()) legend.add(drawTeamLegend(g, s, legend.y + legend.height + 6));
        drawScaleBar(g, t);
        return legend;
    }

    // roam-plot's window: ground truth, surveyed beacons and the start; estimates widen it by at
    // most half its size (a diverged estimate does not shrink everything else); with no ground
    // truth, the estimates themselves.
    static WorldTransform fitted(MapModel.Snapshot s, Set<String> hidden, int width, int height) {
        final Box core = new Box();
        if (s.truthPath != null) core.addAll(s.truthPath);
        for (MapModel.Beacon b : s.beacons) core.add(b.x, b.y);
        if (s.start != null) core.add(s.start[0], s.start[1]);
        for (MapModel.RobotTruth r : s.robots) {
            if (r.path != null) core.addAll(r.path);
            if (r.start != null) core.add(r.start[0], r.start[1]);
        }
        if (core.empty()) {
            for (MapModel.Track t : s.tracks) {
                if (hidden.contains(t.name)) continue;
                core.addAll(t.path);
                for (MapModel.Beacon b : t.map) core.add(b.x, b.y);
            }
        }
        if (core.empty()) core.add(0, 0);
        final double cap = 0.5 * Math.max(Math.max(core.xHi - core.xLo, core.yHi - core.yLo), 1.0);
        final Box box = core.copy();
        for (MapModel.Track t : s.tracks) {
            if (hidden.contains(t.name)) continue;
            box.widen(t.path, core, cap);
            for (MapModel.Beacon b : t.map) box.widenPoint(b.x, b.y, core, cap);
        }
        return WorldTransform.fit(box.xLo, box.xHi, box.yLo, box.yHi, width, height, MARGIN_PX);
    }

    /**
     * The fit for s, or `previous` (an earlier fit) while it still shows everything the new fit
     * would and is not much smaller in scale: a growing path does not move the picture (and force
     * a new layer) on every frame.
     */
    static WorldTransform fittedSticky(WorldTransform previous, MapModel.Snapshot s, Set<String> hidden, int width,
                                       int height) {
        final WorldTransform fit = fitted(s, hidden, width, height);
        if (previous == null || previous.widthPx != width || previous.heightPx != height) return fit;
        if (previous.scalePxPerM > fit.scalePxPerM * 1.000001 || previous.scalePxPerM < 0.8 * fit.scalePxPerM) return fit;
        // The new fit's content (inside its margin) must lie inside the previous one's view.
        final double xLo = fit.worldX(MARGIN_PX), xHi = fit.worldX(width - MARGIN_PX);
        final double yHi = fit.worldY(MARGIN_PX), yLo = fit.worldY(height - MARGIN_PX);
        final boolean inside = previous.px(xLo) >= 0 && previous.px(xHi) <= width && previous.py(yHi) >= 0
                               && previous.py(yLo) <= height;
        return inside ? previous : fit;
    }

    /** The colour mixed 2:3 with white. */
    static Color pale(Color c) {
        return new Color(255 - (255 - c.getRed()) * 2 / 5, 255 - (255 - c.getGreen()) * 2 / 5, 255 - (255 - c.getBlue()) * 2 / 5);
    }

    // Polylines go to the rasteriser in short pieces: one long path that crosses the picture many
    // times makes every scan line carry hundreds of edges (a Plaza path at 16 estimators took
    // ~90 ms a frame as whole shapes). Pieces share their end points; round caps hide the seams.
    private static final int PIECE_POINTS = 48;

    private static void hints(Graphics2D g) {
        g.setRenderingHint(RenderingHints.KEY_ANTIALIASING, RenderingHints.VALUE_ANTIALIAS_ON);
        g.setRenderingHint(RenderingHints.KEY_STROKE_CONTROL, RenderingHints.VALUE_STROKE_PURE);
    }

    private static double last(double[][] path) {
        return path[2].length == 0 ? Double.NEGATIVE_INFINITY : path[2][path[2].length - 1];
    }

    /** The index the tail after `until` starts at: the last point at or before it (so it joins). */
    static int tailStart(double[][] path, double until) {
        int i = java.util.Arrays.binarySearch(path[2], until);
        if (i < 0) i = -i - 2;  // the last one before
        return Math.max(0, i);
    }

    /** Draws xy's points from index `from` on. */
    private static void drawPolyline(Graphics2D g, WorldTransform t, double[][] xy, int from) {
        final int n = xy[0].length;
        Path2D.Double p = new Path2D.Double(Path2D.WIND_NON_ZERO, PIECE_POINTS + 1);
        int inPiece = 0;
        double lastX = 0, lastY = 0;
        for (int i = from; i < n; ++i) {
            if (!Double.isFinite(xy[0][i]) || !Double.isFinite(xy[1][i])) {
                if (inPiece > 1) g.draw(p);
                p = new Path2D.Double(Path2D.WIND_NON_ZERO, PIECE_POINTS + 1);
                inPiece = 0;
                continue;
            }
            final double x = t.px(xy[0][i]), y = t.py(xy[1][i]);
            if (inPiece == 0) {
                p.moveTo(x, y);
            } else if (i == n - 1 || Math.abs(x - lastX) + Math.abs(y - lastY) >= MIN_STEP_PX) {
                p.lineTo(x, y);
            } else {
                continue;  // under a pixel from the last point drawn
            }
            lastX = x;
            lastY = y;
            if (++inPiece == PIECE_POINTS) {
                g.draw(p);
                p = new Path2D.Double(Path2D.WIND_NON_ZERO, PIECE_POINTS + 1);
                p.moveTo(x, y);
                inPiece = 1;
            }
        }
        if (inPiece > 1) g.draw(p);
    }

    private static void drawMap(Graphics2D g, WorldTransform t, MapModel.Track track, Color colour) {
        g.setColor(colour);
        for (MapModel.Beacon b : track.map) {
            if (!Double.isFinite(b.x) || !Double.isFinite(b.y)) continue;
            final double x = t.px(b.x), y = t.py(b.y);
            final double[] e = twoSigmaEllipse(b.cxx, b.cxy, b.cyy);
            if (e != null) {
                final double rx = Math.max(e[0] * t.scalePxPerM, 0.5), ry = Math.max(e[1] * t.scalePxPerM, 0.5);
                final AffineTransform saved = g.getTransform();
                g.translate(x, y);
                g.rotate(-e[2]);  // y points down on screen
                g.setStroke(ELLIPSE);
                g.draw(new Ellipse2D.Double(-rx, -ry, 2 * rx, 2 * ry));
                g.setTransform(saved);
            }
            g.setStroke(CROSS);
            g.draw(new Line2D.Double(x - 5, y - 5, x + 5, y + 5));
            g.draw(new Line2D.Double(x - 5, y + 5, x + 5, y - 5));
        }
    }

    /**
     * The 2-sigma ellipse of the covariance [[a, b], [b, c]]: {major, minor, angle} (metres,
     * radians counter-clockwise from +x), or null when it is not a covariance (paths_figure.cpp).
     */
    static double[] twoSigmaEllipse(double a, double b, double c) {
        if (!Double.isFinite(a) || !Double.isFinite(b) || !Double.isFinite(c)) return null;
        final double mean = 0.5 * (a + c), radius = Math.hypot(0.5 * (a - c), b);
        final double l1 = mean + radius, l2 = mean - radius;
        if (l2 < -1e-12 * Math.max(1.0, Math.abs(l1)) || l1 <= 0) return null;
        return new double[] {2 * Math.sqrt(l1), 2 * Math.sqrt(Math.max(l2, 0)), 0.5 * Math.atan2(2 * b, a - c)};
    }

    private static void drawTrueBeacon(Graphics2D g, double x, double y) {
        final Path2D.Double tri = new Path2D.Double();
        tri.moveTo(x, y - 7);
        tri.lineTo(x + 6.5, y + 4.5);
        tri.lineTo(x - 6.5, y + 4.5);
        tri.closePath();
        g.setColor(Palette.TRUE_BEACON);
        g.fill(tri);
        g.setColor(Palette.OUTLINE);
        g.setStroke(new BasicStroke(1.4f));
        g.draw(tri);
    }

    private static void drawStart(Graphics2D g, double x, double y) {
        g.setColor(Color.WHITE);
        g.fill(new Ellipse2D.Double(x - 5, y - 5, 10, 10));
        g.setColor(Palette.OUTLINE);
        g.setStroke(new BasicStroke(2f));
        g.draw(new Ellipse2D.Double(x - 5, y - 5, 10, 10));
    }

    // Grid lines every "nice" step (1, 2 or 5 x 10^k m) about 100 px apart.
    private static void drawGrid(Graphics2D g, WorldTransform t) {
        final double step = niceStep(100 / t.scalePxPerM);
        g.setColor(GRID);
        g.setStroke(new BasicStroke(1f));
        for (double x = Math.ceil(t.worldX(0) / step) * step; x <= t.worldX(t.widthPx); x += step)
            g.draw(new Line2D.Double(t.px(x), 0, t.px(x), t.heightPx));
        for (double y = Math.ceil(t.worldY(t.heightPx) / step) * step; y <= t.worldY(0); y += step)
            g.draw(new Line2D.Double(0, t.py(y), t.widthPx, t.py(y)));
    }

    static double niceStep(double raw) {
        final double decade = Math.pow(10, Math.floor(Math.log10(raw)));
        final double f = raw / decade;
        return (f < 1.5 ? 1 : f < 3.5 ? 2 : f < 7.5 ? 5 : 10) * decade;
    }

    private static void drawScaleBar(Graphics2D g, WorldTransform t) {
        final double metres = niceStep(120 / t.scalePxPerM);
        final double len = metres * t.scalePxPerM;
        final int x = 16, y = t.heightPx - 16;
        g.setColor(Palette.OUTLINE);
        g.setStroke(new BasicStroke(2f));
        g.draw(new Line2D.Double(x, y, x + len, y));
        g.draw(new Line2D.Double(x, y - 4, x, y + 4));
        g.draw(new Line2D.Double(x + len, y - 4, x + len, y + 4));
        g.setFont(FONT);
        g.drawString((metres >= 1 ? String.format("%.0f m", metres) : String.format("%.2g m", metres)), x, y - 7);
    }

    // roam-plot's legend of marks; the estimators' colours are the checkboxes beside the map.
    private static Rectangle drawLegend(Graphics2D g) {
        final String[] labels = {"ground truth", "start", "true beacon", "estimated beacon", "2\u03C3 ellipse",
                                 "POSE_ path", "latest TRAJECTORY_ (pale)"};
        g.setFont(FONT);
        final int row = 16, x0 = 8, y0 = 8, swatch = 24;
        int w = 0;
        for (String l : labels) w = Math.max(w, g.getFontMetrics().stringWidth(l));
        g.setColor(new Color(255, 255, 255, 230));
        g.fillRect(x0, y0, swatch + w + 20, labels.length * row + 8);
        g.setColor(Palette.FRAME);
        g.setStroke(new BasicStroke(1f));
        g.drawRect(x0, y0, swatch + w + 20, labels.length * row + 8);
        for (int i = 0; i < labels.length; ++i) {
            final double mid = y0 + 4 + i * row + row / 2.0, sx = x0 + 6, cx = sx + swatch / 2.0;
            switch (i) {
                case 0: g.setColor(Palette.TRUTH); g.setStroke(TRUTH); g.draw(new Line2D.Double(sx, mid, sx + swatch, mid)); break;
                case 1: drawStart(g, cx, mid); break;
                case 2: drawTrueBeacon(g, cx, mid + 1); break;
                case 3:
                    g.setColor(Palette.LEGEND_GREY);
                    g.setStroke(CROSS);
                    g.draw(new Line2D.Double(cx - 5, mid - 5, cx + 5, mid + 5));
                    g.draw(new Line2D.Double(cx - 5, mid + 5, cx + 5, mid - 5));
                    break;
                case 4: g.setColor(Palette.LEGEND_GREY); g.setStroke(ELLIPSE); g.draw(new Ellipse2D.Double(cx - 11, mid - 6, 22, 12)); break;
                case 5: g.setColor(Palette.LEGEND_GREY); g.setStroke(PATH); g.draw(new Line2D.Double(sx, mid, sx + swatch, mid)); break;
                default: g.setColor(pale(Palette.series(0))); g.setStroke(TRAJECTORY); g.draw(new Line2D.Double(sx, mid, sx + swatch, mid)); break;
            }
            g.setColor(Palette.OUTLINE);
            g.drawString(labels[i], x0 + swatch + 12, (float) (mid + 4));
        }
        return new Rectangle(x0, y0, swatch + w + 20 + 1, labels.length * row + 8 + 1);
    }

    // A team's legend below the marks': each robot's colour, then each estimator's line style.
    private static Rectangle drawTeamLegend(Graphics2D g, MapModel.Snapshot s, int y0) {
        final int rows = s.robots.size() + s.estimators.size();
        final String[] labels = new String[rows];
        for (int i = 0; i < s.robots.size(); ++i) labels[i] = "robot " + s.robots.get(i).name;
        for (int i = 0; i < s.estimators.size(); ++i)
            labels[s.robots.size() + i] = s.estimators.get(i) + " (" + styleName(i) + ")";
        g.setFont(FONT);
        final int row = 16, x0 = 8, swatch = 24;
        int w = 0;
        for (String l : labels) w = Math.max(w, g.getFontMetrics().stringWidth(l));
        g.setColor(new Color(255, 255, 255, 230));
        g.fillRect(x0, y0, swatch + w + 20, rows * row + 8);
        g.setColor(Palette.FRAME);
        g.setStroke(new BasicStroke(1f));
        g.drawRect(x0, y0, swatch + w + 20, rows * row + 8);
        for (int i = 0; i < rows; ++i) {
            final double mid = y0 + 4 + i * row + row / 2.0, sx = x0 + 6;
            if (i < s.robots.size()) {
                g.setColor(Palette.series(s.robots.get(i).colourIndex));
                g.setStroke(PATH);
            } else {
                g.setColor(Palette.OUTLINE);
                g.setStroke(teamPath(i - s.robots.size()));
            }
            g.draw(new Line2D.Double(sx, mid, sx + swatch, mid));
            g.setColor(Palette.OUTLINE);
            g.drawString(labels[i], x0 + swatch + 12, (float) (mid + 4));
        }
        return new Rectangle(x0, y0, swatch + w + 20 + 1, rows * row + 8 + 1);
    }

    /** A growing bounding box. */
    private static final class Box {
        double xLo = Double.POSITIVE_INFINITY, xHi = Double.NEGATIVE_INFINITY;
        double yLo = Double.POSITIVE_INFINITY, yHi = Double.NEGATIVE_INFINITY;

        void add(double x, double y) {
            if (!Double.isFinite(x) || !Double.isFinite(y)) return;
            xLo = Math.min(xLo, x); xHi = Math.max(xHi, x);
            yLo = Math.min(yLo, y); yHi = Math.max(yHi, y);
        }

        void addAll(double[][] xy) {
            for (int i = 0; i < xy[0].length; ++i) add(xy[0][i], xy[1][i]);
        }

        void widenPoint(double x, double y, Box core, double cap) {
            if (!Double.isFinite(x) || !Double.isFinite(y)) return;
            add(Math.max(core.xLo - cap, Math.min(core.xHi + cap, x)), Math.max(core.yLo - cap, Math.min(core.yHi + cap, y)));
        }

        void widen(double[][] xy, Box core, double cap) {
            for (int i = 0; i < xy[0].length; ++i) widenPoint(xy[0][i], xy[1][i], core, cap);
        }

        boolean empty() {
            return !(xLo <= xHi);
        }

        Box copy() {
            final Box b = new Box();
            b.xLo = xLo; b.xHi = xHi; b.yLo = yLo; b.yHi = yHi;
            return b;
        }
    }
}
