"""Pictures of a design: the Meshcat scene, its local server and the headless-browser check.

:mod:`~springbalance.viz.scene` builds the scene of a result (arm, springs as helices coloured by
tension or magenta below the clearance margin, their name labels, anchor regions, animation) from
:mod:`~springbalance.viz.helix`, :mod:`~springbalance.viz.colors` and :mod:`~springbalance.viz.arm`;
it is recorded in memory for a static page (:mod:`~springbalance.viz.recorder`) or drawn on a live
server on 127.0.0.1 (:mod:`~springbalance.viz.live`, which runs :mod:`~springbalance.viz.server` in a
child process).
:mod:`~springbalance.viz.browser` renders a page in headless Chromium and checks its pixels.
"""
