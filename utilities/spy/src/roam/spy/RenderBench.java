package roam.spy;

import java.awt.Graphics2D;
import java.awt.image.BufferedImage;
import java.io.EOFException;
import java.io.File;
import java.io.IOException;
import java.util.Collections;
import java.util.Set;
import java.util.regex.Pattern;
import javax.imageio.ImageIO;
import lcm.logging.Log;

/**
 * The map of a whole result log, drawn off screen: every message the view subscribes to is fed
 * through the same decoder and model, then the map's layer (MapPainter.Layer: everything drawn
 * anew) and a frame on a kept layer are drawn `repeats` times each and their CPU time printed
 * (thread CPU, so a busy machine does not inflate it) (what the render thread costs at the end of a run), and the last frame written.
 *   java -cp ... roam.spy.RenderBench LOG PNG [WIDTHxHEIGHT] [REPEATS]
 */
public final class RenderBench {
    private RenderBench() {}

    public static void main(String[] args) throws IOException {
        if (args.length < 2) {
            System.err.println("usage: RenderBench LOG PNG [WIDTHxHEIGHT] [REPEATS]");
            System.exit(2);
        }
        final int width = args.length > 2 ? Integer.parseInt(args[2].split("x")[0]) : 760;
        final int height = args.length > 2 ? Integer.parseInt(args[2].split("x")[1]) : 860;
        final int repeats = args.length > 3 ? Integer.parseInt(args[3]) : 20;
        final Pattern drawn = Pattern.compile(BusListener.CHANNELS);
        final MapModel model = new MapModel();
        final Log log = new Log(args[0], "r");
        long messages = 0;
        final long t0 = System.nanoTime();
        try {
            for (;;) {
                final Log.Event e = log.readNext();
                if (!drawn.matcher(e.channel).matches()) continue;
                BusListener.decode(model, e.channel, e.data);
                ++messages;
            }
        } catch (EOFException end) {
            log.close();
        }
        final double decodeMs = (System.nanoTime() - t0) / 1e6;
        final MapModel.Snapshot s = model.snapshot();
        final WorldTransform t = MapPainter.fitted(s, Collections.<String>emptySet(), width, height);
        final java.lang.management.ThreadMXBean cpu = java.lang.management.ManagementFactory.getThreadMXBean();
        BufferedImage image = null;
        final Set<String> none = Collections.<String>emptySet();
        final MapPainter.Layer layer = MapPainter.layer(null, s, none, t);
        final double[] layerMs = new double[2], frameMs = new double[2];  // {mean of the second half, best}
        for (int pass = 0; pass < 2; ++pass) {
            final double[] out = pass == 0 ? layerMs : frameMs;
            long best = Long.MAX_VALUE, total = 0;
            for (int i = 0; i < repeats; ++i) {
                final long start = cpu.getCurrentThreadCpuTime();
                if (pass == 0) {
                    MapPainter.layer(null, s, none, t);  // everything drawn anew
                } else {
                    image = new BufferedImage(width, height, BufferedImage.TYPE_INT_RGB);
                    final Graphics2D g = image.createGraphics();
                    MapPainter.draw(g, s, none, t, layer);  // a frame on the kept layer
                    g.dispose();
                }
                final long took = cpu.getCurrentThreadCpuTime() - start;
                best = Math.min(best, took);
                if (i >= repeats / 2) total += took;  // the second half, after the JIT
            }
            out[0] = total / 1e6 / (repeats - repeats / 2);
            out[1] = best / 1e6;
        }
        ImageIO.write(image, "png", new File(args[1]));
        System.out.printf("%d messages decoded in %.0f ms (%.1f us each); %d estimators; %dx%d, CPU: layer %.1f ms"
                              + " (best %.1f), frame on it %.1f ms (best %.1f)%n",
                          messages, decodeMs, 1e3 * decodeMs / Math.max(messages, 1), s.tracks.size(), width, height,
                          layerMs[0], layerMs[1], frameMs[0], frameMs[1]);
    }
}
