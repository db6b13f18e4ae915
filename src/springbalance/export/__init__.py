"""Exports of a balanced arm for other tools: a URDF with the spring anchors and records
(:mod:`springbalance.export.urdf`) and a MuJoCo model with tendon and joint springs
(:mod:`springbalance.export.mjcf`); :mod:`springbalance.export.common` holds what they share.

The exports read a design's numbers (:class:`~springbalance.design.evaluated.EvaluatedDesign`);
they import nothing from :mod:`springbalance.results` or :mod:`springbalance.io`.
"""
