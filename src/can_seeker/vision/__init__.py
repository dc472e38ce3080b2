"""Finding the can in an image: image decoding, the red detector, the per-frame report."""
