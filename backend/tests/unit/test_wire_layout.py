"""Pins every generated type to the project's wire-layout table, tests/data/umaa-3.0.1-wire-layout.toml:
type names, member names, order and types, keys, optionals, bounds, enum literals and topic names."""

from __future__ import annotations

import importlib
import re
import struct
import tomllib
import typing
from pathlib import Path

import pytest
from cyclonedds.idl import IdlEnum, IdlStruct

from sem_console.dds.topics import Sem

LAYOUT = tomllib.loads((Path(__file__).parents[1] / "data" / "umaa-3.0.1-wire-layout.toml").read_text())
STRUCTS = {s["name"]: s for s in LAYOUT["struct"]}
FLAGS = {"key": "k", "optional": "o", "": None}


def render(hint: typing.Any) -> tuple[str, bool]:
    """An IDL-like spelling of a generated member type, in the wire-layout table's notation, and whether it is optional."""
    optional = False
    if typing.get_origin(hint) is typing.Union:
        (hint,) = [a for a in typing.get_args(hint) if a is not type(None)]
        optional = True
    if typing.get_origin(hint) is typing.Annotated:
        base, meta = typing.get_args(hint)[0], typing.get_args(hint)[1]
        text = str(meta)
        if "NumericGUID" in text:
            return "NumericGUID", optional
        simple = {"float64": "double", "int32": "long", "int64": "long long"}
        if text in simple:
            return simple[text], optional
        if text.startswith("bounded_str["):
            return f"string<{text[12:-1]}>", optional
        if text.startswith("sequence["):
            inner = typing.get_args(base)[0]
            elem = render(inner)[0]
            bound = text[:-1].split(", ")[-1] if ", " in text else None
            return (f"sequence<{elem},{bound}>" if bound else f"sequence<{elem}>"), optional
        raise AssertionError(f"unexpected annotation {text}")
    if hint is bool:
        return "boolean", optional
    if isinstance(hint, type) and issubclass(hint, (IdlStruct, IdlEnum)):
        return hint.__name__, optional
    raise AssertionError(f"unexpected member type {hint!r}")


def layout(cls: type) -> list[tuple[str, str, str | None]]:
    """(type, name, 'k' | 'o' | None) per member, in the generated order."""
    hints = typing.get_type_hints(cls, include_extras=True)
    keys = {n for n, a in getattr(cls, "__idl_field_annotations__", {}).items() if a.get("key")}
    out = []
    for name in cls.__annotations__:
        t, optional = render(hints[name])
        out.append((t, name, "k" if name in keys else "o" if optional else None))
    return out


def members(struct: str) -> list[tuple[str, str, str | None]]:
    """(type, name, 'k' | 'o' | None) per member of a struct, as the table has them."""
    return [(m["type"], m["name"], FLAGS[m.get("flag", "")]) for m in STRUCTS[struct]["members"]]


def gen_class(qualified: str) -> type:
    module, _, name = qualified.replace("::", ".").rpartition(".")
    return getattr(importlib.import_module(module), name)


TOPIC_TYPES = [name for name, s in STRUCTS.items() if "topic" in s]


def test_the_table_lists_every_sem_topic() -> None:
    assert len(TOPIC_TYPES) == len(Sem) == 10
    assert {STRUCTS[t]["topic"] for t in TOPIC_TYPES} == {s.spec.name for s in Sem}


@pytest.mark.parametrize("qualified", TOPIC_TYPES)
def test_topic_type_members_keys_and_names(qualified: str) -> None:
    cls = gen_class(qualified)
    assert cls.__idl_typename__.replace(".", "::") == qualified
    assert layout(cls) == members(qualified)
    specs = [s.spec for s in Sem if s.spec.type is cls]
    assert [s.name for s in specs] == [STRUCTS[qualified]["topic"]]


@pytest.mark.parametrize("name", ["GPSSatelliteType", "GPSClockType"])
def test_nested_types_all_optional(name: str) -> None:
    qualified = f"UMAA::SEM::GPSStatus::{name}"
    cls = gen_class(qualified)
    assert cls.__idl_typename__ == f"UMAA.SEM.GPSStatus.{name}"
    assert layout(cls) == members(qualified)
    assert {flag for _t, _n, flag in members(qualified)} == {"o"}


def test_enums_literal_order_and_type_names() -> None:
    assert len(LAYOUT["enums"]) == 7
    for name, literals in LAYOUT["enums"].items():
        cls = gen_class(f"UMAA::Common::MaritimeEnumeration::{name}::{name}")
        assert cls.__idl_typename__.replace(".", "::") == f"UMAA::Common::MaritimeEnumeration::{name}::{name}"
        assert [e.name for e in cls] == literals
        assert [e.value for e in cls] == list(range(len(cls)))


def test_common_types() -> None:
    common = [n for n in STRUCTS if n.startswith("UMAA::Common::Measurement::")]
    assert len(common) == 9
    for name in common:
        cls = gen_class(name)
        assert cls.__idl_typename__ == name.replace("::", ".")
        assert layout(cls) == members(name)
    assert LAYOUT["typedefs"]["NumericGUID"] == "octet[16]"
    guid = typing.get_type_hints(gen_class("UMAA::SEM::GPSFixControl::GPSFixCommandType"), include_extras=True)["source"]
    assert str(typing.get_args(guid)[1]) == "typedef[UMAA.Common.Measurement.NumericGUID, array[byte, 16]]"


def test_no_extensibility_annotation_in_idl() -> None:
    idl = Path(__file__).resolve().parents[3] / "idl"
    for f in idl.rglob("*.idl"):
        assert not re.search(r"@(final|appendable|mutable|extensibility)", f.read_text()), f


# --- UMAA 6.0 (tests/data/umaa-6.0-wire-layout.toml, the package UMAA_6_0) ------------------------------------------

LAYOUT_6_0 = tomllib.loads((Path(__file__).parents[1] / "data" / "umaa-6.0-wire-layout.toml").read_text())
STRUCTS_6_0 = {s["name"]: s for s in LAYOUT_6_0["struct"]}
TOPIC_TYPES_6_0 = [name for name, s in STRUCTS_6_0.items() if "topic" in s]


def gen_class_6_0(qualified: str) -> type:
    """The UMAA_6_0 class of a 6.0 IDL type name (its wire name stays UMAA::...)."""
    module, _, name = qualified.replace("::", ".").removeprefix("UMAA.").rpartition(".")
    return getattr(importlib.import_module(f"UMAA_6_0.{module}"), name)


def members_6_0(struct: str) -> list[tuple[str, str, str | None]]:
    return [(m["type"], m["name"], FLAGS[m.get("flag", "")]) for m in STRUCTS_6_0[struct]["members"]]


def test_6_0_topics_are_named_after_their_types() -> None:
    assert len(TOPIC_TYPES_6_0) == 6
    assert all(STRUCTS_6_0[t]["topic"] == t for t in TOPIC_TYPES_6_0)


@pytest.mark.parametrize("qualified", list(STRUCTS_6_0))
def test_6_0_struct_members_keys_and_names(qualified: str) -> None:
    cls = gen_class_6_0(qualified)
    assert cls.__idl_typename__.replace(".", "::") == qualified
    assert layout(cls) == members_6_0(qualified)


def test_6_0_enums_literal_order_and_type_names() -> None:
    assert len(LAYOUT_6_0["enums"]) == 7
    for name, literals in LAYOUT_6_0["enums"].items():
        qualified = f"UMAA::Common::MaritimeEnumeration::{name.removesuffix('Type')}Module::{name}"
        cls = gen_class_6_0(qualified)
        assert cls.__idl_typename__.replace(".", "::") == qualified
        assert [e.name for e in cls] == literals
        assert [e.value for e in cls] == list(range(len(cls)))


def test_6_0_identities() -> None:
    guid = typing.get_type_hints(gen_class_6_0("UMAA::Common::IdentifierType"), include_extras=True)["id"]
    assert str(typing.get_args(guid)[1]) == "typedef[UMAA.Common.Measurement.NumericGUID, array[byte, 16]]"


class Cdr:
    """CDR written by hand from the rules of DDS-XTypes 1.3, 7.4: little endian, each primitive aligned to its size
    counted from the end of the 4-byte encapsulation header, at most to 8 (XCDR1) or 4 (XCDR2); an enum is a 32-bit
    ordinal, a boolean one octet, a string its length with the NUL then its octets and the NUL, a sequence its
    length then its elements; in XCDR2 an @optional member of a final struct is a presence octet, then the member."""

    def __init__(self, version: int) -> None:
        self.max_align = 8 if version == 1 else 4
        self.body = bytearray()
        self.header = b"\x00\x01\x00\x00" if version == 1 else b"\x00\x07\x00\x00"  # CDR_LE, PLAIN_CDR2_LE

    def _put(self, fmt: str, value: typing.Any) -> Cdr:
        size = struct.calcsize(fmt)
        self.body += bytes(-len(self.body) % min(size, self.max_align))
        self.body += struct.pack("<" + fmt, value)
        return self

    def i32(self, v: int) -> Cdr:
        return self._put("i", v)

    def i64(self, v: int) -> Cdr:
        return self._put("q", v)

    def f64(self, v: float) -> Cdr:
        return self._put("d", v)

    def boolean(self, v: bool) -> Cdr:
        return self._put("?", v)

    def octets(self, v: bytes) -> Cdr:
        self.body += v
        return self

    def string(self, v: str) -> Cdr:
        data = v.encode() + b"\x00"
        return self.i32(len(data)).octets(data)

    def optional(self, v: float | None) -> Cdr:
        self.boolean(v is not None)
        return self if v is None else self.f64(v)

    def bytes(self) -> bytes:
        return self.header + bytes(self.body)


A, B, C, D = (bytes(range(i, i + 16)) for i in (0x10, 0x20, 0x30, 0x40))
NIL = bytes(16)


def _enum(qualified_enum: str, literal: str) -> typing.Any:
    return gen_class_6_0(qualified_enum)[literal]


def _mar(name: str, literal: str) -> typing.Any:
    return _enum(f"UMAA::Common::MaritimeEnumeration::{name.removesuffix('Type')}Module::{name}", literal)


def _ident(id_: bytes, parent: bytes) -> typing.Any:
    return gen_class_6_0("UMAA::Common::IdentifierType")(id=id_, parentID=parent)


def _time(s: int, ns: int) -> typing.Any:
    return gen_class_6_0("UMAA::Common::Measurement::DateTime")(seconds=s, nanoseconds=ns)


def _golden_gps_report() -> tuple[typing.Any, bytes]:
    clock = gen_class_6_0("UMAA::SEM::GPSStatus::GPSClockType")(
        bias=-5,
        biasUncertainty=7,
        drift=-3,
        driftUncertainty=2,
        elapsedRealtime=123456789012,
        elapsedRealtimeUncertainty=9,
        fullBias=-1234567890123,
        hardwareClockDiscontinuityCount=1,
        leapSecond=18,
        referenceCarrierFrequency=1575.42e6,
        referenceCodeTypeFor="C",
        referenceConstellationType=_mar("GPSConstellationEnumType", "GPS"),
        time=42,
        timeFigureOfMerit=_mar("TFOMEnumType", "TFOM_3"),
    )
    sat = gen_class_6_0("UMAA::SEM::GPSStatus::GPSSatelliteType")(
        antennaCarrierNoiseDensity=45.5,
        azimuth=1.25,
        basebandCarrierNoiseDensity=40.0,
        carrierFrequency=1575.42e6,
        constellationType=_mar("GPSConstellationEnumType", "GALILEO"),
        containsAlmanacData=True,
        elevation=0.5,
        ephemerisData=False,
        satelliteID=17.0,
        usedInFix=True,
    )
    sample = gen_class_6_0("UMAA::SEM::GPSStatus::GPSReportType")(
        clock=clock, numberSatellitesInView=9, satellites=[sat], timeStamp=_time(1_790_000_000, 500), source=_ident(A, B)
    )
    w = Cdr(1)
    w.i64(-5).i64(7).i32(-3).i32(2).i64(123456789012).i64(9).i64(-1234567890123).i64(1).i32(18).f64(1575.42e6)
    w.string("C").i32(3).i32(42).i32(2)  # GPS is ordinal 3; TFOM_3 is 2
    w.i32(9).i32(1)  # numberSatellitesInView; the sequence's length
    w.f64(45.5).f64(1.25).f64(40.0).f64(1575.42e6).i32(1).boolean(True).f64(0.5).boolean(False).f64(17.0).boolean(True)
    w.i64(1_790_000_000).i32(500).octets(A + B)
    return sample, w.bytes()


def _command(state: str) -> typing.Any:
    return gen_class_6_0("UMAA::SEM::InertialSensorControl::InertialSensorCommandType")(
        state=_mar("InertialSensorCmdEnumType", state),
        timeStamp=_time(1_790_000_001, 7),
        source=_ident(A, NIL),
        sessionID=C,
        destination=_ident(B, D),
    )


def _command_bytes(w: Cdr, ordinal: int) -> Cdr:
    return w.i32(ordinal).i64(1_790_000_001).i32(7).octets(A + NIL + C + B + D)


def _golden_command() -> tuple[typing.Any, bytes]:
    return _command("GPS_ALIGN"), _command_bytes(Cdr(1), 1).bytes()


def _golden_status() -> tuple[typing.Any, bytes]:
    sample = gen_class_6_0("UMAA::SEM::InertialSensorControl::InertialSensorCommandStatusType")(
        timeStamp=_time(1_790_000_002, 0),
        source=_ident(B, D),
        sessionID=C,
        commandStatus=_mar("CommandStatusEnumType", "ISSUED"),
        commandStatusReason=_mar("CommandStatusReasonEnumType", "UPDATED"),
        logMessage="updated",
    )
    w = Cdr(1).i64(1_790_000_002).i32(0).octets(B + D + C).i32(5).i32(8).string("updated")
    return sample, w.bytes()


def _golden_ack() -> tuple[typing.Any, bytes]:
    sample = gen_class_6_0("UMAA::SEM::InertialSensorControl::InertialSensorCommandAckReportType")(
        command=_command("STATIONARY_ALIGN"), timeStamp=_time(1_790_000_003, 9), source=_ident(B, D), sessionID=C
    )
    w = _command_bytes(Cdr(1), 4).i64(1_790_000_003).i32(9).octets(B + D + C)
    return sample, w.bytes()


def _golden_ins_report() -> tuple[typing.Any, bytes]:
    sample = gen_class_6_0("UMAA::SEM::InertialSensorStatus::InertialSensorReportType")(
        status=_mar("InertialSensorOpStatusEnumType", "FINE_GPS_ALIGNMENT_STARTED"), timeStamp=_time(1, 2), source=_ident(B, D)
    )
    return sample, Cdr(1).i32(8).i64(1).i32(2).octets(B + D).bytes()


def _golden_global_pose() -> tuple[typing.Any, bytes]:
    o = "UMAA::Common::Orientation::"
    attitude = gen_class_6_0(o + "Orientation3DNEDType")(
        pitch=gen_class_6_0(o + "PitchYNEDType")(pitch=0.1),
        roll=gen_class_6_0(o + "RollXNEDType")(roll=-0.2),
        yaw=gen_class_6_0(o + "YawZNEDType")(yaw=1.5),
    )
    covariance = gen_class_6_0("UMAA::Common::Measurement::CovariancePositionNEDType")(
        pdPd=None, pePd=None, pePe=2.0, pnPd=None, pnPe=0.5, pnPn=3.0
    )
    sample = gen_class_6_0("UMAA::SA::GlobalPoseStatus::GlobalPoseReportType")(
        altitude=None,
        altitudeAGL=None,
        altitudeASF=None,
        altitudeGeodetic=12.5,
        attitude=attitude,
        attitudeCovariance=None,
        course=3.0,
        depth=None,
        navigationSolution=_mar("NavigationSolutionEnumType", "MEASURED"),
        position=gen_class_6_0("UMAA::Common::Measurement::GeoPosition2D")(geodeticLatitude=36.85, geodeticLongitude=-75.98),
        positionCovariance=covariance,
        timeStamp=_time(1_790_000_004, 250),
        source=_ident(B, D),
    )
    # XCDR2: the type has @optional members; 8-byte values align to 4
    w = Cdr(2).optional(None).optional(None).optional(None).optional(12.5)
    w.f64(0.1).f64(-0.2).f64(1.5).boolean(False).f64(3.0).optional(None).i32(2).f64(36.85).f64(-75.98)
    w.boolean(True).optional(None).optional(None).f64(2.0).optional(None).optional(0.5).f64(3.0)
    w.i64(1_790_000_004).i32(250).octets(B + D)
    return sample, w.bytes()


GOLDEN_6_0 = {
    "UMAA::SEM::GPSStatus::GPSReportType": _golden_gps_report,
    "UMAA::SEM::InertialSensorControl::InertialSensorCommandType": _golden_command,
    "UMAA::SEM::InertialSensorControl::InertialSensorCommandStatusType": _golden_status,
    "UMAA::SEM::InertialSensorControl::InertialSensorCommandAckReportType": _golden_ack,
    "UMAA::SEM::InertialSensorStatus::InertialSensorReportType": _golden_ins_report,
    "UMAA::SA::GlobalPoseStatus::GlobalPoseReportType": _golden_global_pose,
}


def test_every_6_0_topic_type_has_golden_bytes() -> None:
    assert sorted(GOLDEN_6_0) == sorted(TOPIC_TYPES_6_0)


@pytest.mark.parametrize("qualified", TOPIC_TYPES_6_0)
def test_6_0_golden_bytes(qualified: str) -> None:
    """A sample of each 6.0 topic type, its bytes worked out by hand from the layout table and the CDR rules: the
    generated type writes exactly those bytes and reads them back to the same sample."""
    sample, golden = GOLDEN_6_0[qualified]()
    assert type(sample) is gen_class_6_0(qualified)
    assert sample.serialize().hex() == golden.hex()
    assert type(sample).deserialize(golden) == sample


def test_the_6_0_topic_table_is_the_layout_table() -> None:
    from sem_console.dds.topics import Sem60

    assert {s.spec.name: s.spec.type for s in Sem60} == {t: gen_class_6_0(t) for t in TOPIC_TYPES_6_0}
