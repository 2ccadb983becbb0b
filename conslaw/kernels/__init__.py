"""Compiled kernels, generated from templates so that numba's on-disk cache works."""
