package roam.spy;

import java.awt.Color;

/**
 * roam-plot's colours (utilities/plot: plot_series.cpp, plot_marks.cpp), so the live view and
 * the figures drawn after a run look alike: the i-th estimator to appear gets the i-th colour of
 * the Okabe-Ito palette (readable by colour-blind people).
 */
final class Palette {
    private static final Color[] SERIES = {
        new Color(0x0072B2), new Color(0xD55E00), new Color(0x009E73), new Color(0xCC79A7),
        new Color(0xE69F00), new Color(0x56B4E9), new Color(0x8C564B), new Color(0x000000)};

    /** Ground truth: #444444 at 35 % opacity, 4 px wide (plot_marks.cpp: truthStroke). */
    static final Color TRUTH = new Color(0x44, 0x44, 0x44, 89);
    /** Surveyed beacon: a yellow triangle with a dark outline (plot_marks.cpp: drawTrueBeacon). */
    static final Color TRUE_BEACON = new Color(0xFFD400);
    static final Color OUTLINE = new Color(0x222222);
    static final Color LEGEND_GREY = new Color(0x555555);
    static final Color FRAME = new Color(0xBBBBBB);

    private Palette() {}

    static Color series(int index) {
        return SERIES[Math.floorMod(index, SERIES.length)];
    }

    static String hex(Color c) {
        return String.format("#%02X%02X%02X", c.getRed(), c.getGreen(), c.getBlue());
    }
}
