"""Installs the pure-Python can_seeker package from src/ (catkin calls this)."""
from setuptools import setup

from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=['can_seeker'], package_dir={'': 'src'}))
