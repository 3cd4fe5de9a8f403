package roam.spy;

import javax.swing.SwingUtilities;

/**
 * The map view on its own, without lcm-spy's table (the same component the plugin opens):
 *   java -cp lcm.jar:lcmtypes_roam.jar:roam_spy.jar roam.spy.MapViewMain [--lcm-url URL]
 *        [--geometry WxH+X+Y] [--snapshot PNG [--snapshot-after S]] [--stats S]
 * Options set the roam.spy.* system properties of ViewOptions.
 */
public final class MapViewMain {
    private MapViewMain() {}

    public static void main(String[] args) {
        for (int i = 0; i < args.length; ++i) {
            final String a = args[i];
            final String[] pair = a.startsWith("--") && a.contains("=") ? a.split("=", 2) : new String[] {a, null};
            final String key = pair[0];
            final String value;
            if (key.equals("-h") || key.equals("--help")) {
                System.out.println("usage: roam-spy --map-only [--lcm-url URL] [--geometry WxH+X+Y] [--snapshot PNG"
                                   + " [--snapshot-after S]] [--stats S]");
                return;
            }
            if (pair[1] != null) value = pair[1];
            else if (i + 1 < args.length) value = args[++i];
            else {
                System.err.println("MapViewMain: " + key + " needs a value");
                System.exit(2);
                return;
            }
            switch (key) {
                case "--lcm-url": case "-l": System.setProperty("roam.spy.lcm_url", value); break;
                case "--geometry": System.setProperty("roam.spy.geometry", value); break;
                case "--snapshot": System.setProperty("roam.spy.snapshot", value); break;
                case "--snapshot-after": System.setProperty("roam.spy.snapshot_after_s", value); break;
                case "--stats": System.setProperty("roam.spy.stats_s", value); break;
                default:
                    System.err.println("MapViewMain: unknown option " + key + " (see --help)");
                    System.exit(2);
                    return;
            }
        }
        try {
            new ViewOptions();  // a bad option fails here, before any window
        } catch (IllegalArgumentException e) {
            System.err.println("MapViewMain: " + e.getMessage());
            System.exit(2);
        }
        SwingUtilities.invokeLater(() -> {
            final MapView view = MapSpyPlugin.open(null);
            ((javax.swing.JFrame) SwingUtilities.getWindowAncestor(view)).setDefaultCloseOperation(
                javax.swing.WindowConstants.EXIT_ON_CLOSE);
        });
    }
}
