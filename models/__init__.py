"""Physical models shipped with conslaw, installed under the import name ``conslaw_models``.

Each module defines one :class:`conslaw.model.Model` subclass and its exact solutions; they are
registered through the ``conslaw.models`` entry-point group, exactly as third-party plugins are.
"""
