"""Windows on a display: whether the display can be opened, and the image windows."""
