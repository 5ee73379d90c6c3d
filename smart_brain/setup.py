from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(
    packages=['smart_brain', 'smart_brain.statemachine', 'smart_brain.strategies', 'smart_brain.triggers',
              'smart_brain.actions', 'smart_brain.play'],
    package_dir={'': 'src'}))
