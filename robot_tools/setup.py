from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(
    packages=['robot_tools', 'robot_tools.report', 'robot_tools.matches', 'robot_tools.chaos',
              'robot_tools.tuning', 'robot_tools.calibration', 'robot_tools.install', 'robot_tools.docs', 'robot_tools.testing'],
    package_dir={'': 'src'}))
