package roam.spy;

import java.awt.Graphics2D;
import java.awt.Point;
import java.awt.Rectangle;
import java.awt.image.BufferedImage;
import java.io.File;
import java.io.IOException;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.StandardCopyOption;
import java.util.Set;
import javax.imageio.ImageIO;
import javax.swing.JComponent;
import javax.swing.SwingUtilities;

/**
 * Writes the view as a PNG and, beside it (PNG + ".txt"), what a test needs to know where a world
 * point must appear in that image, from the same paint: the canvas's place in the image and the
 * world-to-canvas transform (WorldTransform), the legend box (marks under it are hidden), and per
 * estimator its colour, whether shown, and the time of its newest pose. Lines of "key values...".
 * The picture is taken on the Swing thread; both files are written by a thread of their own,
 * under temporary names and renamed, PNG last, so a reader that sees the PNG sees both whole.
 */
final class SnapshotWriter {
    private SnapshotWriter() {}

    static void write(JComponent view, MapCanvas canvas, String stats, String pngPath)
        throws IOException {
        final BufferedImage image = new BufferedImage(view.getWidth(), view.getHeight(), BufferedImage.TYPE_INT_RGB);
        final Graphics2D g = image.createGraphics();
        view.paint(g);
        g.dispose();
        final MapCanvas.Frame frame = canvas.paintedFrame();
        if (frame == null) throw new IOException("the map has not been drawn yet");
        final WorldTransform t = frame.transform;
        final Point at = SwingUtilities.convertPoint(canvas, 0, 0, view);
        final Rectangle legend = frame.legend;
        final MapModel.Snapshot s = frame.snapshot;
        final Set<String> hidden = frame.hidden;

        final File png = new File(pngPath);
        final File sidecar = new File(pngPath + ".txt");
        final File pngTmp = new File(pngPath + ".tmp.png");
        final File sidecarTmp = new File(pngPath + ".txt.tmp");
        final StringBuilder text = new StringBuilder();
        final java.util.Formatter w = new java.util.Formatter(text, java.util.Locale.ROOT);
        w.format("image %d %d%n", image.getWidth(), image.getHeight());
        w.format("canvas %d %d %d %d%n", at.x, at.y, t.widthPx, t.heightPx);
        w.format("transform %.17g %.17g %.17g%n", t.scalePxPerM, t.centreXm, t.centreYm);
        w.format("# px = canvas_x + canvas_w/2 + (x - centre_x) * scale;  py = canvas_y + canvas_h/2 - (y - centre_y) * scale%n");
        w.format("legend %d %d %d %d%n", at.x + legend.x, at.y + legend.y, legend.width, legend.height);
        w.format("ground_truth_last_utime %d%n", s.truthLastUtime);
        w.format("beacons %d%n", s.beacons.size());
        for (MapModel.Track track : s.tracks) {
            w.format("estimator %s %s %s %d %d%n", track.name, Palette.hex(Palette.series(track.colourIndex)),
                     hidden.contains(track.name) ? "hidden" : "shown", track.hasPose ? track.lastUtime : 0,
                     track.path[0].length);
        }
        w.format("stats %s%n", stats);
        // Encoding a PNG takes a good part of a second: not on the Swing thread.
        final Thread writer = new Thread(() -> {
            try {
                Files.write(sidecarTmp.toPath(), text.toString().getBytes(StandardCharsets.UTF_8));
                ImageIO.write(image, "png", pngTmp);
                Files.move(sidecarTmp.toPath(), sidecar.toPath(), StandardCopyOption.REPLACE_EXISTING);
                Files.move(pngTmp.toPath(), png.toPath(), StandardCopyOption.REPLACE_EXISTING);
                System.out.println("roam map view: snapshot " + pngPath);
            } catch (IOException | RuntimeException e) {
                System.err.println("roam map view: cannot write " + pngPath + ": " + e);
            }
        }, "roam-map-snapshot");
        writer.start();
    }
}
