package roam.spy;

/**
 * World (metres, x right, y up) to canvas pixels (x right, y down), uniform scale:
 *   px = width/2 + (x - centreX) * scale,   py = height/2 - (y - centreY) * scale.
 * The view writes these numbers next to each snapshot so a test can compute where a world point
 * must appear.
 */
final class WorldTransform {
    final double scalePxPerM;
    final double centreXm;
    final double centreYm;
    final int widthPx;
    final int heightPx;

    WorldTransform(double scalePxPerM, double centreXm, double centreYm, int widthPx, int heightPx) {
        this.scalePxPerM = scalePxPerM;
        this.centreXm = centreXm;
        this.centreYm = centreYm;
        this.widthPx = widthPx;
        this.heightPx = heightPx;
    }

    double px(double x) {
        return widthPx / 2.0 + (x - centreXm) * scalePxPerM;
    }

    double py(double y) {
        return heightPx / 2.0 - (y - centreYm) * scalePxPerM;
    }

    double worldX(double px) {
        return centreXm + (px - widthPx / 2.0) / scalePxPerM;
    }

    double worldY(double py) {
        return centreYm - (py - heightPx / 2.0) / scalePxPerM;
    }

    /** The box [xLo, xHi] x [yLo, yHi] fitted into width x height with a margin, centred. */
    static WorldTransform fit(double xLo, double xHi, double yLo, double yHi, int widthPx, int heightPx, int marginPx) {
        final double w = Math.max(xHi - xLo, 1.0), h = Math.max(yHi - yLo, 1.0);
        final double scale = Math.min((widthPx - 2.0 * marginPx) / w, (heightPx - 2.0 * marginPx) / h);
        return new WorldTransform(Math.max(scale, 1e-6), 0.5 * (xLo + xHi), 0.5 * (yLo + yHi), widthPx, heightPx);
    }
}
