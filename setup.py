"""setuptools' build with baobab's step: the wheel carries compiled kernels (tools/baobab_build)."""

from baobab_build import BuildPyWithKernels  # on the path as pyproject.toml's backend-path
from setuptools import setup

setup(cmdclass={"build_py": BuildPyWithKernels})
