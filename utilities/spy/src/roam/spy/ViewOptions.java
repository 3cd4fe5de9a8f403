package roam.spy;

/**
 * The map view's settings, from system properties so that lcm-spy (which instantiates the
 * plugin itself) and MapViewMain configure it alike; roam-spy sets them from its arguments.
 *   roam.spy.lcm_url        the bus (default: $LCM_DEFAULT_URL, else LCM's default)
 *   roam.spy.open_map       "true": open the map view as soon as lcm-spy loads the plugin
 *   roam.spy.geometry       WxH+X+Y of the map view's window (default 1280x800+0+0)
 *   roam.spy.repaint_hz     repaint rate bound (default 15, from 1 to 60)
 *   roam.spy.snapshot       a PNG to write of the view (with a .txt sidecar: the transform)
 *   roam.spy.snapshot_after_s   when, in seconds after the view opens (default 10)
 *   roam.spy.stats_s        print the keeping-up statistics to stdout this often (0: never)
 */
final class ViewOptions {
    String lcmUrl = System.getProperty("roam.spy.lcm_url", "");
    boolean openMap = Boolean.getBoolean("roam.spy.open_map");
    int width = 1280;
    int height = 800;
    int x = 0;
    int y = 0;
    double repaintHz = number("roam.spy.repaint_hz", 15, 1, 60);
    String snapshot = System.getProperty("roam.spy.snapshot", "");
    double snapshotAfterS = number("roam.spy.snapshot_after_s", 10, 0, 1e6);
    double statsS = number("roam.spy.stats_s", 0, 0, 1e6);

    ViewOptions() {
        final String g = System.getProperty("roam.spy.geometry", "");
        if (!g.isEmpty()) {
            final java.util.regex.Matcher m =
                java.util.regex.Pattern.compile("(\\d+)x(\\d+)(?:\\+(\\d+)\\+(\\d+))?").matcher(g);
            if (!m.matches()) throw new IllegalArgumentException("roam.spy.geometry: expected WxH+X+Y, got '" + g + "'");
            width = Integer.parseInt(m.group(1));
            height = Integer.parseInt(m.group(2));
            if (m.group(3) != null) {
                x = Integer.parseInt(m.group(3));
                y = Integer.parseInt(m.group(4));
            }
        }
    }

    private static double number(String key, double fallback, double lo, double hi) {
        final String text = System.getProperty(key, "");
        if (text.isEmpty()) return fallback;
        final double v;
        try {
            v = Double.parseDouble(text);
        } catch (NumberFormatException e) {
            throw new IllegalArgumentException(key + ": expected a number, got '" + text + "'");
        }
        if (!(v >= lo && v <= hi)) throw new IllegalArgumentException(key + ": expected " + lo + " to " + hi + ", got " + text);
        return v;
    }
}
