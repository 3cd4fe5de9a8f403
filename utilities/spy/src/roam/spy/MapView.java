package roam.spy;

import java.awt.BorderLayout;
import java.awt.Color;
import java.awt.FlowLayout;
import java.awt.Font;
import java.io.IOException;
import java.util.ArrayList;
import java.util.HashSet;
import java.util.List;
import java.util.Set;
import javax.swing.BorderFactory;
import javax.swing.BoxLayout;
import javax.swing.JButton;
import javax.swing.JLabel;
import javax.swing.JPanel;
import javax.swing.JScrollPane;
import javax.swing.ScrollPaneConstants;
import javax.swing.Timer;

/**
 * roam's live map: the canvas, a row per estimator beside it (checkbox in its colour, error
 * against ground truth, STATUS_ line), and a footer (fit, clear, show all / none, how well the
 * view keeps up). A Swing timer takes a snapshot of the model at a bounded rate, only when
 * something arrived, and hands it to the canvas's render thread.
 * The same component opens from lcm-spy's channel menu (MapSpyPlugin) and from MapViewMain.
 */
final class MapView extends JPanel {
    private final ViewOptions options;
    private final MapModel model = new MapModel();
    private final Stats stats = new Stats();
    private final MapCanvas canvas;
    private final JPanel rows = new JPanel();
    private final List<EstimatorRow> rowList = new ArrayList<>();
    private final Set<String> hidden = new HashSet<>();
    private final JLabel footer = new JLabel(" ");
    private final Timer timer;
    private BusListener listener;
    private long shownVersion = -1;
    private MapModel.Snapshot current = new MapModel.Snapshot();
    private long lastStatsNs = System.nanoTime();

    MapView(ViewOptions options) {
        super(new BorderLayout());
        this.options = options;
        canvas = new MapCanvas(stats, options.repaintHz);
        add(canvas, BorderLayout.CENTER);

        rows.setLayout(new BoxLayout(rows, BoxLayout.Y_AXIS));
        rows.setBackground(Color.WHITE);
        final JPanel rowsTop = new JPanel(new BorderLayout());  // rows at the top, not spread out
        rowsTop.setBackground(Color.WHITE);
        rowsTop.add(rows, BorderLayout.NORTH);
        final JScrollPane side = new JScrollPane(rowsTop, ScrollPaneConstants.VERTICAL_SCROLLBAR_AS_NEEDED,
                                                 ScrollPaneConstants.HORIZONTAL_SCROLLBAR_AS_NEEDED);
        side.setPreferredSize(new java.awt.Dimension(400, 600));
        side.setBorder(BorderFactory.createMatteBorder(0, 1, 0, 0, Palette.FRAME));
        add(side, BorderLayout.EAST);

        final JPanel buttons = new JPanel(new FlowLayout(FlowLayout.LEFT, 6, 2));
        final JButton fit = new JButton("Fit");
        fit.setToolTipText("fit ground truth and beacons again (or double-click the map); wheel zooms, drag pans");
        fit.addActionListener(e -> canvas.fitAgain());
        final JButton clear = new JButton("Clear");
        clear.setToolTipText("forget everything received (a new replay)");
        clear.addActionListener(e -> model.clear());
        final JButton all = new JButton("All");
        all.addActionListener(e -> setAllShown(true));
        final JButton none = new JButton("None");
        none.addActionListener(e -> setAllShown(false));
        for (JButton b : new JButton[] {fit, clear, all, none}) buttons.add(b);
        footer.setFont(footer.getFont().deriveFont(Font.PLAIN, 11f));
        footer.setBorder(BorderFactory.createEmptyBorder(0, 8, 0, 4));
        final JPanel bottom = new JPanel(new BorderLayout());
        bottom.add(buttons, BorderLayout.WEST);
        bottom.add(footer, BorderLayout.CENTER);
        add(bottom, BorderLayout.SOUTH);

        timer = new Timer((int) Math.round(1000.0 / options.repaintHz), e -> tick());
        timer.setCoalesce(true);  // a slow paint skips ticks rather than queueing them
    }

    /** Subscribes and starts repainting. */
    void start() throws IOException {
        listener = new BusListener(options.lcmUrl, model, stats);
        System.out.println("roam map view: listening on " + (options.lcmUrl.isEmpty() ? "LCM's default URL" : options.lcmUrl)
                           + (listener.receiveBufferBytes > 0 ? " (receive buffer " + listener.receiveBufferBytes + " bytes)" : ""));
        timer.start();
        if (!options.snapshot.isEmpty()) {
            final Timer once = new Timer((int) Math.round(options.snapshotAfterS * 1000), e -> writeSnapshot());
            once.setRepeats(false);
            once.start();
        }
    }

    void stop() {
        timer.stop();
        canvas.stop();
        if (listener != null) listener.close();
        listener = null;
    }

    private long lastTickNs;

    private void tick() {
        final long now = System.nanoTime();
        if (lastTickNs != 0) stats.recordSwingDelay(now - lastTickNs - timer.getDelay() * 1_000_000L);
        lastTickNs = now;
        if (options.statsS > 0 && System.nanoTime() - lastStatsNs >= options.statsS * 1e9) {
            lastStatsNs = System.nanoTime();
            System.out.println("roam map view: " + statsLine());
        }
        footer.setText(statsLine());
        final long version = model.version();
        if (version == shownVersion) return;
        shownVersion = version;
        current = model.snapshot();
        syncRows(current);
        canvas.setSnapshot(current, hidden);
    }

    String statsLine() {
        return stats.line(listener == null ? 0 : listener.backlog());
    }

    private void syncRows(MapModel.Snapshot s) {
        boolean changed = rowList.size() != s.tracks.size();
        for (int i = 0; !changed && i < s.tracks.size(); ++i) changed = !rowList.get(i).name.equals(s.tracks.get(i).name);
        if (changed) {
            rows.removeAll();
            rowList.clear();
            for (MapModel.Track t : s.tracks) {
                final EstimatorRow row = new EstimatorRow(t.name, Palette.series(t.colourIndex), this::readCheckboxes);
                row.shown.setSelected(!hidden.contains(t.name));
                rowList.add(row);
                rows.add(row);
            }
            rows.revalidate();
        }
        final boolean truthOnBus = s.truthPath != null || !s.robots.isEmpty();
        for (int i = 0; i < rowList.size(); ++i) rowList.get(i).update(s.tracks.get(i), truthOnBus);
    }

    private void readCheckboxes() {
        hidden.clear();
        for (EstimatorRow r : rowList)
            if (!r.shown.isSelected()) hidden.add(r.name);
        canvas.setSnapshot(current, hidden);
    }

    private void setAllShown(boolean shown) {
        for (EstimatorRow r : rowList) r.shown.setSelected(shown);
        readCheckboxes();
    }

    private void writeSnapshot() {
        try {
            SnapshotWriter.write(this, canvas, statsLine(), options.snapshot);
        } catch (IOException | RuntimeException e) {
            System.err.println("roam map view: cannot write " + options.snapshot + ": " + e);
        }
    }
}
