"""Command-line tools beside the nodes: demo, evaluate, bag_detect, benchmarks, their harness.

Like the nodes these are ROS glue; the logic they drive lives in the pure subpackages.
"""
