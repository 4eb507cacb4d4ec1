"""The helpers of the tests: a PostgreSQL cluster, DDS peers and consumers, sample generators."""
