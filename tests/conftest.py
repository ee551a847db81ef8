"""Shared test settings."""

from hypothesis import HealthCheck, settings

# Integration inside properties is slower than hypothesis' default 200 ms deadline.
settings.register_profile("tumble", deadline=None, suppress_health_check=[HealthCheck.too_slow])
settings.load_profile("tumble")
