"""Foxglove live: the fleet, read-only, to Foxglove or Lichtblick over the Foxglove WebSocket protocol (docs/foxglove.md)."""
