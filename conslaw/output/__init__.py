"""The output files of a run, by format; :mod:`conslaw.io` is the public face."""
