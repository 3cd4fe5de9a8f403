package roam.spy;

import java.awt.Dimension;
import java.awt.Graphics;
import java.awt.Graphics2D;
import java.awt.Rectangle;
import java.awt.event.ComponentAdapter;
import java.awt.event.ComponentEvent;
import java.awt.event.MouseAdapter;
import java.awt.event.MouseEvent;
import java.awt.event.MouseWheelEvent;
import java.awt.image.BufferedImage;
import java.util.Collections;
import java.util.HashSet;
import java.util.Set;
import javax.swing.JComponent;

/**
 * The map on screen. A render thread draws the newest snapshot into an image (MapPainter) at
 * most `hz` times a second, only when something changed, and never more than a third of the
 * time (a slow frame delays the next); the Swing thread only copies the
 * finished image, so a map of sixteen long paths never holds up Swing (lcm-spy's table included).
 * Until the user zooms (wheel) or pans (drag) the view fits ground truth and beacons
 * (roam-plot's window); a double click fits again.
 */
final class MapCanvas extends JComponent {
    /** A finished picture, with what it shows and the transform it was drawn with. */
    static final class Frame {
        final BufferedImage image;
        final WorldTransform transform;
        final Rectangle legend;
        final MapModel.Snapshot snapshot;
        final Set<String> hidden;

        Frame(BufferedImage image, WorldTransform transform, Rectangle legend, MapModel.Snapshot snapshot,
              Set<String> hidden) {
            this.image = image;
            this.transform = transform;
            this.legend = legend;
            this.snapshot = snapshot;
            this.hidden = hidden;
        }
    }

    private static final java.lang.management.ThreadMXBean CPU = java.lang.management.ManagementFactory.getThreadMXBean();
    private final Stats stats;
    private final long periodNs;
    private final Object lock = new Object();  // guards everything below up to `frame`
    private MapModel.Snapshot snapshot = new MapModel.Snapshot();
    private Set<String> hidden = Collections.emptySet();
    private boolean autoFit = true;
    private double userScale;
    private double userCentreX;
    private double userCentreY;
    private int width;
    private int height;
    private boolean dirty = true;
    private boolean running = true;
    private volatile Frame frame;
    private Frame painted;  // the frame the last paintComponent showed (Swing thread)
    private int dragX;
    private int dragY;

    MapCanvas(Stats stats, double hz) {
        this.stats = stats;
        this.periodNs = (long) (1e9 / hz);
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
                synchronized (lock) {
                    if (!freeze()) return;
                    userCentreX -= (e.getX() - dragX) / userScale;
                    userCentreY += (e.getY() - dragY) / userScale;
                    changed();
                }
                dragX = e.getX();
                dragY = e.getY();
            }

            @Override
            public void mouseWheelMoved(MouseWheelEvent e) {
                synchronized (lock) {
                    if (!freeze()) return;
                    // Zoom about the point under the cursor: it stays where it is.
                    final WorldTransform t = new WorldTransform(userScale, userCentreX, userCentreY, width, height);
                    final double wx = t.worldX(e.getX()), wy = t.worldY(e.getY());
                    userScale *= Math.pow(1.2, -e.getPreciseWheelRotation());
                    userCentreX = wx - (e.getX() - width / 2.0) / userScale;
                    userCentreY = wy + (e.getY() - height / 2.0) / userScale;
                    changed();
                }
            }

            @Override
            public void mouseClicked(MouseEvent e) {
                if (e.getClickCount() == 2) fitAgain();
            }
        };
        addMouseListener(mouse);
        addMouseMotionListener(mouse);
        addMouseWheelListener(mouse);
        addComponentListener(new ComponentAdapter() {
            @Override
            public void componentResized(ComponentEvent e) {
                synchronized (lock) {
                    width = getWidth();
                    height = getHeight();
                    changed();
                }
            }
        });
        final Thread renderer = new Thread(this::renderLoop, "roam-map-renderer");
        renderer.setDaemon(true);
        renderer.start();
    }

    void setSnapshot(MapModel.Snapshot s, Set<String> hiddenNames) {
        synchronized (lock) {
            snapshot = s;
            hidden = new HashSet<>(hiddenNames);
            changed();
        }
    }

    void fitAgain() {
        synchronized (lock) {
            autoFit = true;
            changed();
        }
    }

    void stop() {
        synchronized (lock) {
            running = false;
            lock.notifyAll();
        }
    }

    /** The frame the last paint showed (what a snapshot's sidecar reports); null before any. */
    Frame paintedFrame() {
        return painted;
    }

    private void changed() {
        dirty = true;
        lock.notifyAll();
    }

    // From auto-fit to the user's own transform, starting from what is on screen.
    private boolean freeze() {
        if (!autoFit) return true;
        final Frame f = frame;
        if (f == null) return false;
        userScale = f.transform.scalePxPerM;
        userCentreX = f.transform.centreXm;
        userCentreY = f.transform.centreYm;
        autoFit = false;
        return true;
    }

    private void renderLoop() {
        long lastNs = System.nanoTime() - periodNs;
        long tookNs = 0;
        MapPainter.Layer layer = null;
        WorldTransform lastFit = null;
        for (;;) {
            final MapModel.Snapshot s;
            final Set<String> h;
            final WorldTransform t;
            try {
                synchronized (lock) {
                    while (running && (!dirty || width <= 0 || height <= 0)) lock.wait();
                    if (!running) return;
                    // The rate bound, and at most a third of a core however long a frame takes.
                    final long wait = lastNs + Math.max(periodNs, 3 * tookNs) - System.nanoTime();
                    if (wait > 0) {
                        lock.wait(wait / 1_000_000, (int) (wait % 1_000_000));
                        continue;
                    }
                    dirty = false;
                    s = snapshot;
                    h = hidden;
                    t = autoFit ? (lastFit = MapPainter.fittedSticky(lastFit, s, h, width, height))
                                : new WorldTransform(userScale, userCentreX, userCentreY, width, height);
                }
            } catch (InterruptedException e) {
                return;
            }
            lastNs = System.nanoTime();
            final long cpuStart = CPU.getCurrentThreadCpuTime();
            final MapPainter.Layer before = layer;
            layer = MapPainter.layer(layer, s, h, t);
            final BufferedImage image = new BufferedImage(t.widthPx, t.heightPx, BufferedImage.TYPE_INT_RGB);
            final Graphics2D g = image.createGraphics();
            final Rectangle legend;
            try {
                legend = MapPainter.draw(g, s, h, t, layer);
            } finally {
                g.dispose();
            }
            frame = new Frame(image, t, legend, s, h);
            tookNs = System.nanoTime() - lastNs;
            stats.recordPaint(tookNs, CPU.getCurrentThreadCpuTime() - cpuStart, layer != before);
            // A layer kept though outdated (built under REBUILD_NS ago) misses what came since,
            // e.g. a team plugin's final trajectories, the last messages of a run: draw again,
            // so the rebuild comes even when nothing more arrives.
            if (layer == before && layer.outdated(s)) {
                synchronized (lock) {
                    dirty = true;
                }
            }
            repaint();
        }
    }

    @Override
    protected void paintComponent(Graphics g) {
        final Frame f = frame;
        painted = f;
        if (f == null) {
            g.setColor(java.awt.Color.WHITE);
            g.fillRect(0, 0, getWidth(), getHeight());
            return;
        }
        g.drawImage(f.image, 0, 0, null);
        if (f.image.getWidth() < getWidth() || f.image.getHeight() < getHeight()) {  // a resize in progress
            g.setColor(java.awt.Color.WHITE);
            g.fillRect(f.image.getWidth(), 0, getWidth() - f.image.getWidth(), getHeight());
            g.fillRect(0, f.image.getHeight(), getWidth(), getHeight() - f.image.getHeight());
        }
    }
}
