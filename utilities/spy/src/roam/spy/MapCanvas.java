package roam.spy;

import java.awt.BasicStroke;
import java.awt.Color;
import java.awt.Dimension;
import java.awt.Font;
import java.awt.Graphics;
import java.awt.Graphics2D;
import java.awt.RenderingHints;
import java.awt.Stroke;
import java.awt.event.MouseAdapter;
import java.awt.event.MouseEvent;
import java.awt.event.MouseWheelEvent;
import java.awt.geom.AffineTransform;
import java.awt.geom.Ellipse2D;
import java.awt.geom.Line2D;
import java.awt.geom.Path2D;
import java.util.Collections;
import java.util.HashSet;
import java.util.Set;
import javax.swing.JComponent;

/**
 * The map, to scale: ground truth, each shown estimator's POSE_ path (solid), latest
 * TRAJECTORY_ (dashed) and MAP_ (crosses with 2-sigma ellipses), surveyed beacons, the start.
 * Styles follow roam-plot (plot_marks.cpp). Until the user zooms (wheel) or pans (drag), the view
 * fits ground truth and beacons (roam-plot's window); a double click fits again.
 */
final class MapCanvas extends JComponent {
    private static final int MARGIN_PX = 24;
    private static final Stroke TRUTH = new BasicStroke(4f, BasicStroke.CAP_ROUND, BasicStroke.JOIN_ROUND);
    private static final Stroke PATH = new BasicStroke(2f, BasicStroke.CAP_ROUND, BasicStroke.JOIN_ROUND);
    private static final Stroke TRAJECTORY = new BasicStroke(1.4f, BasicStroke.CAP_BUTT, BasicStroke.JOIN_ROUND, 10f,
                                                             new float[] {6f, 4f}, 0f);
    private static final Stroke ELLIPSE = new BasicStroke(1f, BasicStroke.CAP_BUTT, BasicStroke.JOIN_ROUND, 10f,
                                                          new float[] {3f, 2f}, 0f);
    private static final Stroke CROSS = new BasicStroke(2.4f);
    private static final Color GRID = new Color(0xECECEC);

    private final Stats stats;
    private MapModel.Snapshot snapshot = new MapModel.Snapshot();
    private Set<String> hidden = Collections.emptySet();
    private boolean autoFit = true;
    private double userScale;
    private double userCentreX;
    private double userCentreY;
    private WorldTransform lastTransform;
    private final java.awt.Rectangle legendRect = new java.awt.Rectangle();
    private int dragX;
    private int dragY;

    MapCanvas(Stats stats) {
        this.stats = stats;
        setPreferredSize(new Dimension(880, 700));
        setOpaque(true);
        final MouseAdapter mouse = new MouseAdapter() {
            @Override
            public void mousePressed(MouseEvent e) {
                dragX = e.getX();
                dragY = e.getY();
            }

            @Override
            public void mouseDragged(MouseEvent e) {
                freeze();
                userCentreX -= (e.getX() - dragX) / userScale;
                userCentreY += (e.getY() - dragY) / userScale;
                dragX = e.getX();
                dragY = e.getY();
                repaint();
            }

            @Override
            public void mouseWheelMoved(MouseWheelEvent e) {
                freeze();
                // Zoom about the point under the cursor: it stays where it is.
                final WorldTransform t = current();
                final double wx = t.worldX(e.getX()), wy = t.worldY(e.getY());
                userScale *= Math.pow(1.2, -e.getPreciseWheelRotation());
                userCentreX = wx - (e.getX() - getWidth() / 2.0) / userScale;
                userCentreY = wy + (e.getY() - getHeight() / 2.0) / userScale;
                repaint();
            }

            @Override
            public void mouseClicked(MouseEvent e) {
                if (e.getClickCount() == 2) fitAgain();
            }
        };
        addMouseListener(mouse);
        addMouseMotionListener(mouse);
        addMouseWheelListener(mouse);
    }

    void setSnapshot(MapModel.Snapshot s, Set<String> hiddenNames) {
        snapshot = s;
        hidden = new HashSet<>(hiddenNames);
    }

    void fitAgain() {
        autoFit = true;
        repaint();
    }

    /** Where the last paint put the legend box (canvas pixels): map marks under it are hidden. */
    java.awt.Rectangle legendRect() {
        return new java.awt.Rectangle(legendRect);
    }

    /** The transform of the last paint (what a snapshot's sidecar reports). */
    WorldTransform lastTransform() {
        return lastTransform;
    }

    private void freeze() {
        if (!autoFit) return;
        final WorldTransform t = current();
        userScale = t.scalePxPerM;
        userCentreX = t.centreXm;
        userCentreY = t.centreYm;
        autoFit = false;
    }

    private WorldTransform current() {
        if (!autoFit) return new WorldTransform(userScale, userCentreX, userCentreY, getWidth(), getHeight());
        return fitted(snapshot, getWidth(), getHeight());
    }

    // roam-plot's window: ground truth, surveyed beacons and the start; estimates widen it by at
    // most half its size (a diverged estimate does not shrink everything else); with no ground
    // truth, the estimates themselves.
    private WorldTransform fitted(MapModel.Snapshot s, int width, int height) {
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

    @Override
    protected void paintComponent(Graphics graphics) {
        final long t0 = System.nanoTime();
        final Graphics2D g = (Graphics2D) graphics.create();
        try {
            g.setRenderingHint(RenderingHints.KEY_ANTIALIASING, RenderingHints.VALUE_ANTIALIAS_ON);
            g.setRenderingHint(RenderingHints.KEY_STROKE_CONTROL, RenderingHints.VALUE_STROKE_PURE);
            g.setColor(Color.WHITE);
            g.fillRect(0, 0, getWidth(), getHeight());
            final MapModel.Snapshot s = snapshot;
            final WorldTransform t = current();
            lastTransform = t;
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
            g.setFont(getFont().deriveFont(Font.PLAIN, 11f));
            for (MapModel.Beacon b : s.beacons) {
                final double x = t.px(b.x), y = t.py(b.y);
                drawTrueBeacon(g, x, y);
                g.setColor(Palette.OUTLINE);
                g.drawString(Integer.toString(b.id), (float) (x + 8), (float) (y - 6));
            }
            drawLegend(g);
            drawScaleBar(g, t);
        } finally {
            g.dispose();
        }
        stats.recordPaint(System.nanoTime() - t0);
    }

    private static Path2D polyline(WorldTransform t, double[][] xy) {
        final Path2D.Double p = new Path2D.Double(Path2D.WIND_NON_ZERO, xy[0].length);
        boolean open = false;
        for (int i = 0; i < xy[0].length; ++i) {
            if (!Double.isFinite(xy[0][i]) || !Double.isFinite(xy[1][i])) {
                open = false;
                continue;
            }
            if (open) p.lineTo(t.px(xy[0][i]), t.py(xy[1][i]));
            else p.moveTo(t.px(xy[0][i]), t.py(xy[1][i]));
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
    private void drawGrid(Graphics2D g, WorldTransform t) {
        final double step = niceStep(100 / t.scalePxPerM);
        g.setColor(GRID);
        g.setStroke(new BasicStroke(1f));
        for (double x = Math.ceil(t.worldX(0) / step) * step; x <= t.worldX(getWidth()); x += step)
            g.draw(new Line2D.Double(t.px(x), 0, t.px(x), getHeight()));
        for (double y = Math.ceil(t.worldY(getHeight()) / step) * step; y <= t.worldY(0); y += step)
            g.draw(new Line2D.Double(0, t.py(y), getWidth(), t.py(y)));
    }

    static double niceStep(double raw) {
        final double decade = Math.pow(10, Math.floor(Math.log10(raw)));
        final double f = raw / decade;
        return (f < 1.5 ? 1 : f < 3.5 ? 2 : f < 7.5 ? 5 : 10) * decade;
    }

    private void drawScaleBar(Graphics2D g, WorldTransform t) {
        final double metres = niceStep(120 / t.scalePxPerM);
        final double len = metres * t.scalePxPerM;
        final int x = 16, y = getHeight() - 16;
        g.setColor(Palette.OUTLINE);
        g.setStroke(new BasicStroke(2f));
        g.draw(new Line2D.Double(x, y, x + len, y));
        g.draw(new Line2D.Double(x, y - 4, x, y + 4));
        g.draw(new Line2D.Double(x + len, y - 4, x + len, y + 4));
        g.setFont(getFont().deriveFont(Font.PLAIN, 11f));
        g.drawString((metres >= 1 ? String.format("%.0f m", metres) : String.format("%.2g m", metres)), x, y - 7);
    }

    // roam-plot's legend of marks; the estimators' colours are the checkboxes beside the map.
    private void drawLegend(Graphics2D g) {
        final String[] labels = {"ground truth", "start", "true beacon", "estimated beacon", "2\u03C3 ellipse",
                                 "POSE_ path", "latest TRAJECTORY_"};
        g.setFont(getFont().deriveFont(Font.PLAIN, 11f));
        final int row = 16, x0 = 8, y0 = 8, swatch = 24;
        int w = 0;
        for (String l : labels) w = Math.max(w, g.getFontMetrics().stringWidth(l));
        legendRect.setBounds(x0, y0, swatch + w + 20 + 1, labels.length * row + 8 + 1);
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
