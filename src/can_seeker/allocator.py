"""The C allocator of a node that receives and sends images every frame.

rospy allocates several image-sized buffers per message (its socket reads ask for buff_size,
16 MiB for images, then the message is copied out of its read buffer) and frees them again.
With glibc's defaults, blocks that large are mapped fresh for each frame and returned to the
kernel when freed, so every frame faults in and zeroes its pages again: about 230 page faults
and ~1 ms of CPU per 640x480 bgr8 frame on this machine (measured with bench_node). Raising the
mmap and trim thresholds keeps freed blocks in the process for the next frame. The memory kept
is what the node needed at its peak anyway; it is not returned to the system while it runs.
"""
import ctypes

# mallopt parameters (glibc malloc.h).
M_TRIM_THRESHOLD = -1
M_MMAP_THRESHOLD = -3

MMAP_THRESHOLD_BYTES = 32 * 1024 * 1024
"""Blocks below this come from the heap, not from fresh mappings: above rospy's 16 MiB image
read buffer; 32 MiB is the most glibc accepts on 64-bit systems."""
TRIM_THRESHOLD_BYTES = 2 * MMAP_THRESHOLD_BYTES
"""Free memory at the heap top kept for reuse (glibc's own rule: twice the mmap threshold)."""


def reuse_freed_memory() -> bool:
    """Let the process reuse the memory of freed image-sized blocks instead of mapping fresh
    pages for each frame. True when the C library took both settings (glibc), False when it
    has no ``mallopt`` (another C library: its defaults stay)."""
    try:
        mallopt = ctypes.CDLL(None).mallopt
    except (AttributeError, OSError):
        return False
    mallopt.argtypes = (ctypes.c_int, ctypes.c_int)
    mallopt.restype = ctypes.c_int
    return bool(mallopt(M_MMAP_THRESHOLD, MMAP_THRESHOLD_BYTES)) and bool(
        mallopt(M_TRIM_THRESHOLD, TRIM_THRESHOLD_BYTES))
