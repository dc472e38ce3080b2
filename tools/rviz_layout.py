#!/usr/bin/python3
"""Lay out the panels of rviz/can_seeker.rviz and save it (the dock layout is a Qt state blob
that cannot be written by hand): Displays over Views on the left, the annotated camera image
on the right, the 3D view between them, at 1280x800; the Time panel closed.

Needs Debian's python3-rviz, a display (Xvfb does) and a ROS master:
  DISPLAY=:99 /usr/bin/python3 tools/rviz_layout.py rviz/can_seeker.rviz
"""
import sys

from python_qt_binding.QtCore import Qt, QTimer
from python_qt_binding.QtWidgets import QApplication, QDockWidget
from rviz import bindings as rviz

WIDTH, HEIGHT = 1280, 800
LEFT_PX, RIGHT_PX = 270, 430


def main(path):
    app = QApplication(sys.argv)
    frame = rviz.VisualizationFrame()
    frame.setSplashPath('')
    frame.initialize()
    config = rviz.Config()
    rviz.YamlConfigReader().readFile(config, path)
    frame.load(config)
    frame.resize(WIDTH, HEIGHT)
    docks = {dock.windowTitle(): dock for dock in frame.findChildren(QDockWidget)}
    print('panels: %s' % ', '.join(sorted(docks)))
    for title, dock in docks.items():
        if title in ('Displays', 'Views'):
            frame.addDockWidget(Qt.LeftDockWidgetArea, dock)
        elif title == 'Time':
            dock.close()
        else:
            frame.addDockWidget(Qt.RightDockWidgetArea, dock)
    frame.show()

    def save():
        frame.resizeDocks([docks['Displays'], docks['Annotated camera']], [LEFT_PX, RIGHT_PX],
                          Qt.Horizontal)
        QTimer.singleShot(500, write)

    def write():
        out = rviz.Config()
        frame.save(out)
        rviz.YamlConfigWriter().writeFile(out, path)
        print('saved %s' % path)
        app.quit()

    QTimer.singleShot(1500, save)
    app.exec_()


if __name__ == '__main__':
    main(sys.argv[1])
