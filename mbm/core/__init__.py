"""The core of mbm: the compiled window loop, one concern per module.

=====================  ==========================================================
:mod:`.record`         the run record (RUN) and its initialiser (new_run)
:mod:`.window`         the approximant kinds and the approximant's step; winding
:mod:`.controller`     the fixed and adaptive controllers
:mod:`.loop`           the window loop and its entries per regime set
:mod:`.emit`           a window's outputs written to the call's rows
:mod:`.kind_ops`       the other kinds' pieces, called through a table of addresses
:mod:`.lanes`          the lockstep lanes of solve_batch
:mod:`.stored`         stored windows evaluated at any times
=====================  ==========================================================

The regimes' hooks into the loop live with their regime in :mod:`mbm.regimes`.
"""
