"""ASPN-23 over LCM: each vehicle's GPSFixReport and GPSReport as ASPN measurements (see README, "Gateways")."""
