package roam.spy;

import java.awt.BasicStroke;
import java.awt.Color;
import java.awt.Component;
import java.awt.Font;
import java.awt.Graphics;
import java.awt.Graphics2D;
import java.awt.RenderingHints;
import javax.swing.BorderFactory;
import javax.swing.BoxLayout;
import javax.swing.Icon;
import javax.swing.JCheckBox;
import javax.swing.JLabel;
import javax.swing.JPanel;

/** One estimator beside the map: a checkbox with its colour (the legend), its error and status. */
final class EstimatorRow extends JPanel {
    final String name;
    final JCheckBox shown;
    private final JLabel error = new JLabel();
    private final JLabel status = new JLabel();
    private final JLabel rejection = new JLabel();
    private final JLabel[] diagnostics = {new JLabel(), new JLabel(), new JLabel(), new JLabel()};
    private static final int LINE_CHARS = 62;

    EstimatorRow(String name, Color colour, Runnable onToggle) {
        this.name = name;
        setLayout(new BoxLayout(this, BoxLayout.Y_AXIS));
        setBorder(BorderFactory.createEmptyBorder(3, 4, 5, 4));
        setBackground(Color.WHITE);
        shown = new JCheckBox(name, new Swatch(colour, false), true);
        shown.setSelectedIcon(new Swatch(colour, true));
        shown.setFont(shown.getFont().deriveFont(Font.BOLD));
        shown.setForeground(colour.darker());
        shown.setOpaque(false);
        shown.addActionListener(e -> onToggle.run());
        add(shown);
        final java.util.List<JLabel> lines = new java.util.ArrayList<>(java.util.Arrays.asList(error, status, rejection));
        lines.addAll(java.util.Arrays.asList(diagnostics));
        for (JLabel l : lines) {
            l.setFont(l.getFont().deriveFont(Font.PLAIN, 11f));
            l.setBorder(BorderFactory.createEmptyBorder(0, 30, 0, 0));
            l.setAlignmentX(Component.LEFT_ALIGNMENT);
            add(l);
        }
        shown.setAlignmentX(Component.LEFT_ALIGNMENT);
    }

    void update(MapModel.Track t, boolean truthOnBus) {
        setText(error, StatusText.error(t, truthOnBus));
        setText(status, StatusText.status(t.status));
        final String why = StatusText.rejection(t.status);
        setText(rejection, why.length() > LINE_CHARS ? why.substring(0, LINE_CHARS - 1) + "\u2026" : why);
        rejection.setToolTipText(why.isEmpty() ? null : why);
        rejection.setVisible(!why.isEmpty());
        // Diagnostics as key=value pairs, wrapped at whole pairs onto up to four lines.
        final String[] pairs = StatusText.diagnostics(t.status);
        int next = 0;
        for (JLabel l : diagnostics) {
            final StringBuilder line = new StringBuilder();
            while (next < pairs.length && (line.length() == 0 || line.length() + 2 + pairs[next].length() <= LINE_CHARS)) {
                if (line.length() > 0) line.append("  ");
                line.append(pairs[next++]);
            }
            setText(l, line.length() > LINE_CHARS ? line.substring(0, LINE_CHARS - 1) + "\u2026" : line.toString());
            l.setVisible(line.length() > 0);
        }
    }

    private static void setText(JLabel l, String text) {
        if (!text.equals(l.getText())) l.setText(text);  // unchanged text: no relayout
    }

    /** A checkbox drawn as the estimator's line colour: filled when shown, hollow when hidden. */
    private static final class Swatch implements Icon {
        private final Color colour;
        private final boolean on;

        Swatch(Color colour, boolean on) {
            this.colour = colour;
            this.on = on;
        }

        @Override
        public void paintIcon(Component c, Graphics graphics, int x, int y) {
            final Graphics2D g = (Graphics2D) graphics.create();
            g.setRenderingHint(RenderingHints.KEY_ANTIALIASING, RenderingHints.VALUE_ANTIALIAS_ON);
            g.setColor(colour);
            g.setStroke(new BasicStroke(2f));
            if (on) g.fillRect(x + 1, y + 3, 22, 10);
            else g.drawRect(x + 2, y + 4, 20, 8);
            g.dispose();
        }

        @Override
        public int getIconWidth() {
            return 26;
        }

        @Override
        public int getIconHeight() {
            return 16;
        }
    }
}
