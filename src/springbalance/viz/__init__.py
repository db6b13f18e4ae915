"""Pictures of a design: the Meshcat scene, its local server and the headless-browser check.

:mod:`~springbalance.viz.scene` is the entry point (``scene_html``, ``show``): it draws a design's
:class:`~springbalance.viz.design_scene.DesignScene` (arm, springs as helices coloured by tension or
solid red below the clearance margin, their name labels, anchor regions, animation), made of the springs'
tracks (:mod:`~springbalance.viz.tracks`, with :mod:`~springbalance.viz.helix` and
:mod:`~springbalance.viz.colors`), the anchors' regions (:mod:`~springbalance.viz.regions`), the arm
(:mod:`~springbalance.viz.arm`, its mesh files decimated by :mod:`~springbalance.viz.arm_meshes`), the
camera (:mod:`~springbalance.viz.camera`) and, on the static page, the HTML name labels and the regions'
checkbox (:mod:`~springbalance.viz.overlay`), and drawn with
springbalance's meshcat classes (:mod:`~springbalance.viz.meshcat_glue`; meshcat itself is imported on
first use, :mod:`~springbalance.viz.meshcat_import`). The scene is recorded in memory for a static page
(:mod:`~springbalance.viz.recorder`) or drawn on a live server on 127.0.0.1
(:mod:`~springbalance.viz.live`, which runs :mod:`~springbalance.viz.server` in a child process).
:mod:`~springbalance.viz.browser` renders a page in headless Chromium and checks its pixels.

The pose slider: the poses a scene shows (:mod:`~springbalance.viz.pose_paths`: a sweep, the workspace, the
worst samples), their numbers (:mod:`~springbalance.viz.pose_data`: forces, residual torques) and the page's
slider and overlay (:mod:`~springbalance.viz.pose_slider`); :mod:`~springbalance.viz.devtools` drives a page in
headless Chromium over the DevTools protocol (the tests move the slider with it).
"""
