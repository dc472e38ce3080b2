"""The package's one ROS edge: message builders, the camera-pose source, node diagnostics and
package paths. Nodes and tools wire topics with these; the pure modules never import them."""
