"""ROS nodes: thin glue that reads parameters, wires topics and calls the pure modules."""
