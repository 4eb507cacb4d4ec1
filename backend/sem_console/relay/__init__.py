"""`sem-relay`: a DDS domain joined to others across a WAN over Eclipse Zenoh (docs/relay.md)."""
