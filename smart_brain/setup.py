from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(packages=['smart_brain', 'smart_brain.strategies'], package_dir={'': 'src'}))
