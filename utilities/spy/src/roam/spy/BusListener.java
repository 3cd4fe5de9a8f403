package roam.spy;

import java.io.IOException;
import java.util.concurrent.ArrayBlockingQueue;
import java.util.concurrent.BlockingQueue;
import java.util.concurrent.TimeUnit;
import lcm.lcm.LCM;
import lcm.lcm.LCMDataInputStream;
import lcm.lcm.LCMSubscriber;
import roam.estimator_status_t;
import roam.map_t;
import roam.pose_t;
import roam.trajectory_t;

/**
 * The view's own LCM subscription. LCM's receive thread only copies each message into a bounded
 * queue (it never blocks: a full queue drops and counts); one decoder thread decodes by type
 * fingerprint and updates the model. Neither is the Swing thread, and neither is lcm-spy's LCM
 * instance, so the view cannot hold up lcm-spy's table.
 */
final class BusListener implements LCMSubscriber {
    private static final int QUEUE = 50000;
    /** The channels the view draws (a regular expression, as LCM subscribes); a team's GROUND_TRUTH_<R> too. */
    static final String CHANNELS = "GROUND_TRUTH(_.+)?|INITIAL_POSE(_.+)?|BEACONS|POSE_.*|MAP_.*|TRAJECTORY_.*|STATUS_.*";

    private static final class Raw {
        final String channel;
        final byte[] data;
        final long receivedNs;
        final long sequence;

        Raw(String channel, byte[] data, long receivedNs, long sequence) {
            this.channel = channel;
            this.data = data;
            this.receivedNs = receivedNs;
            this.sequence = sequence;
        }
    }

    // A whole path replaces the previous one: a TRAJECTORY_ still queued when a newer one on its
    // channel arrives is skipped undecoded (a Plaza-length one takes milliseconds to decode).
    private final java.util.concurrent.ConcurrentHashMap<String, Long> newestTrajectory =
        new java.util.concurrent.ConcurrentHashMap<>();
    private long sequence;  // LCM's receive thread only

    private final MapModel model;
    private final Stats stats;
    private final BlockingQueue<Raw> queue = new ArrayBlockingQueue<>(QUEUE);
    private final LCM lcm;
    private final Thread decoder;
    private volatile boolean running = true;
    /** The UDP receive buffer the kernel granted (0: not a udpm:// bus, or unknown). */
    final int receiveBufferBytes;
    private static final int WANTED_RECEIVE_BUFFER = 8 << 20;

    BusListener(String url, MapModel model, Stats stats) throws IOException {
        this.model = model;
        this.stats = stats;
        lcm = (url == null || url.isEmpty()) ? new LCM() : new LCM(url);
        receiveBufferBytes = widenReceiveBuffer(lcm);
        decoder = new Thread(this::decodeLoop, "roam-map-decoder");
        decoder.setDaemon(true);
        decoder.start();
        lcm.subscribe(CHANNELS, this);
    }

    /**
     * Asks for a large UDP receive buffer (the kernel caps it at net.core.rmem_max). LCM's Java
     * library has no URL option for it, and the default (net.core.rmem_default, often 208 KB) is
     * less than one Plaza-length TRAJECTORY_ (~310 KB in five 64 KB fragments): sixteen smoothers
     * publishing at once would overflow it. Reaches LCM's socket by reflection (LCM 1.3.1:
     * LCM.providers, UDPMulticastProvider.sock); on any other layout it changes nothing.
     */
    static int widenReceiveBuffer(LCM lcm) {
        try {
            final java.lang.reflect.Field providers = LCM.class.getDeclaredField("providers");
            providers.setAccessible(true);
            int granted = 0;
            for (Object provider : (java.util.List<?>) providers.get(lcm)) {
                for (java.lang.reflect.Field f : provider.getClass().getDeclaredFields()) {
                    if (!java.net.DatagramSocket.class.isAssignableFrom(f.getType())) continue;
                    f.setAccessible(true);
                    final java.net.DatagramSocket socket = (java.net.DatagramSocket) f.get(provider);
                    if (socket == null) continue;
                    socket.setReceiveBufferSize(WANTED_RECEIVE_BUFFER);
                    granted = socket.getReceiveBufferSize();
                }
            }
            return granted;
        } catch (ReflectiveOperationException | RuntimeException | java.net.SocketException e) {
            return 0;
        }
    }

    /** Roam's output and reference types, by fingerprint (the first 8 bytes of a message). */
    static boolean isRoamType(long fingerprint) {
        return fingerprint == pose_t.LCM_FINGERPRINT || fingerprint == map_t.LCM_FINGERPRINT
            || fingerprint == trajectory_t.LCM_FINGERPRINT
            || fingerprint == estimator_status_t.LCM_FINGERPRINT
            || fingerprint == roam.odometry_t.LCM_FINGERPRINT
            || fingerprint == roam.range_t.LCM_FINGERPRINT;
    }

    @Override
    public void messageReceived(LCM from, String channel, LCMDataInputStream ins) {
        final byte[] data = new byte[ins.available()];
        try {
            ins.readFully(data);
        } catch (IOException e) {
            stats.errors.incrementAndGet();
            return;
        }
        stats.received.incrementAndGet();
        final long seq = ++sequence;
        if (channel.startsWith("TRAJECTORY_")) newestTrajectory.put(channel, seq);
        if (!queue.offer(new Raw(channel, data, System.nanoTime(), seq))) stats.dropped.incrementAndGet();
    }

    private void decodeLoop() {
        while (running) {
            final Raw raw;
            try {
                raw = queue.poll(200, TimeUnit.MILLISECONDS);
            } catch (InterruptedException e) {
                return;
            }
            if (raw == null) continue;
            final Long newest = newestTrajectory.get(raw.channel);
            if (newest != null && newest != raw.sequence) {
                stats.superseded.incrementAndGet();
                continue;
            }
            try {
                decode(raw);
            } catch (IOException | RuntimeException e) {
                stats.errors.incrementAndGet();
            }
            stats.recordLag(System.nanoTime() - raw.receivedNs);
        }
    }

    private void decode(Raw raw) throws IOException {
        if (!decode(model, raw.channel, raw.data)) stats.ignored.incrementAndGet();
    }

    /** Decodes one message into the model by its type; false when it is no type the view draws. */
    static boolean decode(MapModel model, String channel, byte[] data) throws IOException {
        if (data.length < 8) throw new IOException("short message on " + channel);
        long fingerprint = 0;
        for (int i = 0; i < 8; ++i) fingerprint = (fingerprint << 8) | (data[i] & 0xFF);
        final LCMDataInputStream in = new LCMDataInputStream(data);
        if (fingerprint == pose_t.LCM_FINGERPRINT) model.onPose(channel, new pose_t(in));
        else if (fingerprint == map_t.LCM_FINGERPRINT) model.onMap(channel, new map_t(in));
        else if (fingerprint == trajectory_t.LCM_FINGERPRINT) model.onTrajectory(channel, new trajectory_t(in));
        else if (fingerprint == estimator_status_t.LCM_FINGERPRINT) model.onStatus(channel, new estimator_status_t(in));
        else return false;  // another type on a matching channel name
        return true;
    }

    void close() {
        running = false;
        lcm.unsubscribe(CHANNELS, this);
        lcm.close();
        decoder.interrupt();
    }

    int backlog() {
        return queue.size();
    }
}
