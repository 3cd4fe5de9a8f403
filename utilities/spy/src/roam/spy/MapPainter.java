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
import java.util.Set;

/**
 * Draws the map, to scale: ground truth, each shown estimator's POSE_ path (solid), latest
 * TRAJECTORY_ (dashed) and MAP_ (crosses with 2-sigma ellipses), its current position, surveyed
 * beacons, the start, a legend of marks and a scale bar. Styles follow roam-plot
 * (plot_marks.cpp). Polylines skip points less than a pixel from the last one drawn, so the cost
 * follows the picture's size, not the path's length. Called off the Swing thread (MapCanvas).
 */
final class MapPainter {
    private static final int MARGIN_PX = 24;
    private static final double MIN_STEP_PX = 1.0;
    private static final Font FONT = new Font(Font.SANS_SERIF, Font.PLAIN, 11);
    private static final Stroke TRUTH = new BasicStroke(4f, BasicStroke.CAP_ROUND, BasicStroke.JOIN_ROUND);
    private static final Stroke PATH = new BasicStroke(2f, BasicStroke.CAP_ROUND, BasicStroke.JOIN_ROUND);
    private static final Stroke TRAJECTORY = new BasicStroke(1.4f, BasicStroke.CAP_BUTT, BasicStroke.JOIN_ROUND, 10f,
                                                             new float[] {6f, 4f}, 0f);
    private static final Stroke ELLIPSE = new BasicStroke(1f, BasicStroke.CAP_BUTT, BasicStroke.JOIN_ROUND, 10f,
                                                          new float[] {3f, 2f}, 0f);
    private static final Stroke CROSS = new BasicStroke(2.4f);
    private static final Color GRID = new Color(0xECECEC);

    private MapPainter() {}

    /** Draws everything into g over t's width x height; returns where the legend box went. */
    static Rectangle draw(Graphics2D g, MapModel.Snapshot s, Set<String> hidden, WorldTransform t) {
        g.setRenderingHint(RenderingHints.KEY_ANTIALIASING, RenderingHints.VALUE_ANTIALIAS_ON);
        g.setRenderingHint(RenderingHints.KEY_STROKE_CONTROL, RenderingHints.VALUE_STROKE_PURE);
        g.setColor(Color.WHITE);
        g.fillRect(0, 0, t.widthPx, t.heightPx);
                    drawGrid(g, t);
        if (s.truthPath != null) {
            g.setColor(Palette.TRUTH);
            g.setStroke(TRUTH);
            g.draw(polyline(t, s.truthPath));
        }
        for (MapModel.Track track : s.tracks) {
            if (hidden.contains(track.name)) continue;
            final Color colour = Palette.series(track.colourIndex);
            g.setColor(colour);
            if (track.trajectory != null) {
                g.setStroke(TRAJECTORY);
                g.draw(polyline(t, track.trajectory));
            }
            g.setStroke(PATH);
            g.draw(polyline(t, track.path));
            drawMap(g, t, track, colour);
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
        g.setFont(FONT);
        for (MapModel.Beacon b : s.beacons) {
            final double x = t.px(b.x), y = t.py(b.y);
            drawTrueBeacon(g, x, y);
            g.setColor(Palette.OUTLINE);
            g.drawString(Integer.toString(b.id), (float) (x + 8), (float) (y - 6));
        }
        final Rectangle legend = drawLegend(g);
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

    private static Path2D polyline(WorldTransform t, double[][] xy) {
        final int n = xy[0].length;
        final Path2D.Double p = new Path2D.Double(Path2D.WIND_NON_ZERO, Math.min(n, 4096));
        boolean open = false;
        double lastX = 0, lastY = 0;
        for (int i = 0; i < n; ++i) {
            if (!Double.isFinite(xy[0][i]) || !Double.isFinite(xy[1][i])) {
                open = false;
                continue;
            }
            final double x = t.px(xy[0][i]), y = t.py(xy[1][i]);
            if (!open) {
                p.moveTo(x, y);
            } else if (i == n - 1 || Math.abs(x - lastX) + Math.abs(y - lastY) >= MIN_STEP_PX) {
                p.lineTo(x, y);
            } else {
                continue;  // under a pixel from the last point drawn
            }
            lastX = x;
            lastY = y;
            open = true;
        }
        return p;
    }

    private static void drawMap(Graphics2D g, WorldTransform t, MapModel.Track track, Color colour) {
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
                                 "POSE_ path", "latest TRAJECTORY_"};
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
                default: g.setColor(Palette.LEGEND_GREY); g.setStroke(TRAJECTORY); g.draw(new Line2D.Double(sx, mid, sx + swatch, mid)); break;
            }
            g.setColor(Palette.OUTLINE);
            g.drawString(labels[i], x0 + swatch + 12, (float) (mid + 4));
        }
        return new Rectangle(x0, y0, swatch + w + 20 + 1, labels.length * row + 8 + 1);
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
