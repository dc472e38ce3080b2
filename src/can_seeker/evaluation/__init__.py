"""Judging runs on ground truth: trial criteria, top-down views, videos, simulator benchmarks."""
