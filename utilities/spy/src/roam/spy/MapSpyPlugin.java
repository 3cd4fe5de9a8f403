package roam.spy;

import java.awt.Window;
import java.awt.event.ActionEvent;
import java.awt.event.WindowAdapter;
import java.awt.event.WindowEvent;
import java.io.IOException;
import javax.swing.AbstractAction;
import javax.swing.Action;
import javax.swing.JDesktopPane;
import javax.swing.JFrame;
import javax.swing.SwingUtilities;
import javax.swing.WindowConstants;
import lcm.spy.ChannelData;
import lcm.spy.SpyPlugin;

/**
 * lcm-spy finds this class on its class path (it instantiates every SpyPlugin it finds) and
 * offers "roam map view" in the context menu of any channel of a roam type. lcm-spy 1.3.1 hands a
 * plugin a fresh window (a JDesktopPane in a JFrame) but not its LCM object, so the view
 * subscribes itself on the same bus: roam-spy passes lcm-spy's URL as roam.spy.lcm_url.
 * With roam.spy.open_map=true the view opens as soon as lcm-spy loads the plugin (tests, or
 * `roam-spy --map`).
 */
public class MapSpyPlugin implements SpyPlugin {
    private static boolean openedAtStart;

    public MapSpyPlugin() {
        synchronized (MapSpyPlugin.class) {
            if (openedAtStart || !Boolean.getBoolean("roam.spy.open_map")) return;
            openedAtStart = true;
        }
        SwingUtilities.invokeLater(() -> open(null));
    }

    @Override
    public boolean canHandle(long fingerprint) {
        return BusListener.isRoamType(fingerprint);
    }

    @Override
    public Action getAction(JDesktopPane desktop, ChannelData channel) {
        return new AbstractAction("roam map view") {
            @Override
            public void actionPerformed(ActionEvent e) {
                open(desktop);
            }
        };
    }

    /** Opens the view in the window lcm-spy made for the plugin (or a new one). */
    static MapView open(JDesktopPane desktop) {
        final ViewOptions options = new ViewOptions();
        final Window spyWindow = desktop == null ? null : SwingUtilities.getWindowAncestor(desktop);
        final JFrame frame = spyWindow instanceof JFrame ? (JFrame) spyWindow : new JFrame();
        frame.setTitle("roam map view" + (options.lcmUrl.isEmpty() ? "" : " \u2014 " + options.lcmUrl));
        final MapView view = new MapView(options);
        frame.setContentPane(view);
        frame.setDefaultCloseOperation(WindowConstants.DISPOSE_ON_CLOSE);
        frame.setBounds(options.x, options.y, options.width, options.height);
        frame.addWindowListener(new WindowAdapter() {
            @Override
            public void windowClosed(WindowEvent e) {
                view.stop();
            }
        });
        frame.validate();
        frame.setVisible(true);
        try {
            view.start();
        } catch (IOException e) {
            System.err.println("roam map view: cannot subscribe to " + options.lcmUrl + ": " + e.getMessage());
        }
        return view;
    }
}
