"""The inputs of each shipped model, apart from its numerics: parameters, initial state,
physical units, scenario keys and the :class:`~tumble.models.base.Declaration` a scenario is
validated against.

These modules load numpy and tumble's validation only, so that a scenario is read and
checked — and an input error reported — in a fraction of a second; each model module
(:mod:`tumble.models.resisting_medium`, …) imports its inputs from here and adds the
equations.
"""
