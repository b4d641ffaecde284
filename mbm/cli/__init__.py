"""The command line (``mbm ...``, ``python -m mbm``) and the studies behind it.

=====================  ==========================================================
:mod:`.main`           the parser and the subcommands (demo, solve, study, iv)
:mod:`.study`          step-size and accuracy studies with fitted orders
:mod:`.orderfit`       convergence orders fitted where a reference's error floors
=====================  ==========================================================

Library code does not import this package.
"""
