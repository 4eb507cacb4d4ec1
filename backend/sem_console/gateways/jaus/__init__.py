"""JAUS over JUDP (AS5669A): ReportNavigation 0x4421 and ReportCommsLostConfiguration 0x4C03 per vehicle (README, "Gateways")."""
