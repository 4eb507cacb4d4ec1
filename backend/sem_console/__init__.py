"""SEM Console: a UMAA Sensor and Effector Management console over DDS."""

__version__ = "0.1.0"
