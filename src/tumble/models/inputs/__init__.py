"""The inputs of each shipped model under their former paths: each model keeps its parameters,
initial state, physical units, scenario keys and :class:`~tumble.models.base.Declaration` in
its own package (``tumble.models.<name>.inputs``), and ``tumble.models.inputs.<name>`` gives the
same names.

These modules load numpy and tumble's validation only, so that a scenario is read and
checked — and an input error reported — in a fraction of a second.
"""
