"""`sem-keys`: the DDS Security documents a fleet needs (docs/security.md, "The DDS bus: sem-keys")."""
