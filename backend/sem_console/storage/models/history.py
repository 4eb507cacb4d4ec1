"""A vehicle's track and chart series (also the REST response models of the track and chart routes)."""

from __future__ import annotations

from sqlmodel import Field, SQLModel

TRACK, SERIES = "track", "series"


class TrackPoint(SQLModel, table=True):
    """One position of a vehicle's track, from its GPSFixReport (at most one per vehicle and UTC second)."""

    __tablename__ = TRACK
    providerId: str = Field(primary_key=True, description="the provider's source GUID as a UUID string")
    time: float = Field(
        primary_key=True, index=True, description="UTC seconds since the epoch when the console received the GPSFixReport"
    )
    positionTime: float | None = Field(description="the report's timeAtPosition, UTC seconds (null: not sent)")
    latitude: float = Field(description="degrees, WGS 84, north positive")
    longitude: float = Field(description="degrees, WGS 84, east positive")
    altitudeMsl: float | None = Field(description="altitude above mean sea level, metres")
    course: float | None = Field(description="true course over ground, degrees 0..360")
    sog: float | None = Field(description="speed over ground, metres per second")
    latLongValid: bool = Field(description="GPSLatLongValid: the position is from GPS (false: from the INS)")
    fixValid: bool | None = Field(description="fixValid of the vehicle's latest GPSFixStatusReport (null: none received yet)")


class SeriesPoint(SQLModel, table=True):
    """The dashboard's chart values of a vehicle at one time, from its GPSReport (at most one per UTC second)."""

    __tablename__ = SERIES
    providerId: str = Field(primary_key=True, description="the provider's source GUID as a UUID string")
    time: float = Field(
        primary_key=True, index=True, description="UTC seconds since the epoch when the console received the GPSReport"
    )
    cn0Mean: float | None = Field(
        description="mean antennaCarrierNoiseDensity (C/N0) of the satellites that report one, dB-Hz (null: none)"
    )
    satellitesUsed: int = Field(description="satellites with usedInFix")
    satellitesInView: int = Field(description="numberSatellitesInView")
