"""The generated decoder (codec/fastcdr.py) against cyclonedds' own deserializer, on random samples of
every SEM type in both encodings the topics use (XCDR1 for types without @optional members, XCDR2 for
all), optional members present and absent: the sample it builds equals cyclonedds' and its JSON equals
`convert.to_json` of cyclonedds' sample, invalid-value messages included. Malformed input (cut short,
flipped bytes, lengths past the end) either decodes to what cyclonedds decodes or raises; the Decoder
counts it and never raises."""

from __future__ import annotations

import math
import random
import struct
from collections.abc import Iterator
from typing import Any

import pytest
from cyclonedds.core import InstanceState
from cyclonedds.idl._support import Endianness

from sem_console.codec import fastcdr
from sem_console.codec.convert import to_json
from sem_console.codec.decode import REPORT_TOPICS, Decoder
from sem_console.dds.topics import Sem, Sem60
from sem_console.versions import umaa_6_0
from support.samplegen import random_sample

SEMS = list(Sem)
N = 150


def encodings(sem: Sem) -> list[tuple[bool, Endianness]]:
    versions = [True] if sem.spec.xcdr2_only else [False, True]
    return [(v2, e) for v2 in versions for e in (Endianness.Little, Endianness.Big)]


def encoded(sem: Sem, rng: random.Random, n: int, **kw: float) -> Iterator[bytes]:
    """`n` random samples of the topic's type, each in every encoding the topic uses."""
    t = sem.spec.type
    for _ in range(n):
        sample = random_sample(t, rng, **kw)
        for v2, endian in encodings(sem):
            yield t.serialize(sample, use_version_2=v2, endianness=endian)


def same(a: object, b: object) -> bool:
    """Equality where NaN equals NaN (random samples have none, malformed ones may)."""
    if isinstance(a, float) and isinstance(b, float):
        return a == b or (math.isnan(a) and math.isnan(b))
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b, strict=True))
    if hasattr(a, "__dataclass_fields__") and type(a) is type(b):
        return all(same(getattr(a, f), getattr(b, f)) for f in a.__dataclass_fields__)
    return (bool(a == b) and type(a) is type(b)) or (isinstance(a, (bytes, bytearray)) and a == b)


@pytest.mark.parametrize("sem", SEMS, ids=[s.name for s in SEMS])
def test_pinned_to_cyclonedds_on_random_samples(sem: Sem) -> None:
    rng = random.Random(sem.name)
    t = sem.spec.type
    dec = fastcdr.decoder(t)
    for i in range(N):
        # every optional member present (the one-unpack layout), none, or some (member by member)
        for data in encoded(sem, rng, 1, absent=(0.0, 1.0, 0.1, 0.4, 0.7)[i % 5]):
            ref = t.deserialize(data)
            assert dec.sample(data) == ref, (i, data.hex())
            assert dec.json(data) == to_json(ref), (i, data.hex())


@pytest.mark.parametrize("sem", list(Sem60), ids=[s.name for s in Sem60])
def test_6_0_types_pinned_to_cyclonedds_on_random_samples(sem: Sem60) -> None:
    """A 6.0 type's samples, optional members present, absent or some, in every encoding a writer may send (XCDR1 when
    the type has no @optional member, XCDR2 both byte orders, an appendable writer's delimited XCDR2): the sample the
    generated decoder builds is cyclonedds' (the source's parentID too), its JSON is `to_json` of it, and a report's
    model JSON is the version's adapter of that."""
    from sem_console.dds.topics import to_appendable

    rng = random.Random(sem.name)
    report = umaa_6_0.REPORTS.get(sem)
    for i in range(60):
        sample = random_sample(sem.spec.type, rng, absent=(0.0, 1.0, 0.1, 0.5, 0.9)[i % 5])
        if i % 6 == 0:
            _values_out_of_range(sample, rng)
        datas = [(sem.spec.type, sem.spec.type.serialize(sample, use_version_2=v2, endianness=e)) for v2, e in encodings(sem)]
        if sem.spec.appendable is not None:
            copy = to_appendable(sample)
            datas += [(type(copy), copy.serialize(use_version_2=True, endianness=e)) for e in (Endianness.Little, Endianness.Big)]
        for t, data in datas:
            ref = t.deserialize(data)
            got = fastcdr.decoder(t).sample(data)
            assert same(got, ref) and bytes(got.source.parentID) == bytes(ref.source.parentID), (i, data.hex())
            plain, invalid = fastcdr.decoder(t).json(data)
            want = to_json(ref)
            assert same(plain, want[0]) and invalid == want[1], (i, data.hex())
            if report is not None and report.spec is not None:
                model = fastcdr.decoder(t, report.spec, umaa_6_0.model_path, report.model).json(data)
                want = report.model(*to_json(ref))
                assert same(model[0], want[0]) and model[1] == want[1], (i, data.hex())


@pytest.mark.parametrize("sem", SEMS, ids=[s.name for s in SEMS])
def test_generated_not_fallen_back(sem: Sem) -> None:
    """Every encoding a SEM topic uses is decoded by generated code, not by cyclonedds."""
    for v2, endian in encodings(sem):
        for json in (False, True):
            source, _ = fastcdr.generate(sem.spec.type, v2, endian == Endianness.Little, json)
            assert source.startswith("def decode(b):")


def _values_out_of_range(sample: object, rng: random.Random) -> None:
    """Put NaN, infinities, out-of-range numbers and unknown enum ordinals into a sample, in place."""
    from dataclasses import fields, is_dataclass

    for f in fields(sample):  # type: ignore[arg-type]
        v = getattr(sample, f.name)
        if isinstance(v, float) and rng.random() < 0.4:
            setattr(sample, f.name, rng.choice([math.nan, math.inf, -math.inf, 1e9, -1e9]))
        elif isinstance(v, int) and not isinstance(v, bool) and f.name == "nanoseconds" and rng.random() < 0.5:
            setattr(sample, f.name, rng.choice([-1, 2_000_000_000]))
        elif is_dataclass(v):
            _values_out_of_range(v, rng)
        elif isinstance(v, list):
            for x in v:
                if is_dataclass(x):
                    _values_out_of_range(x, rng)


@pytest.mark.parametrize("sem", [s for s in SEMS if s in REPORT_TOPICS], ids=lambda s: s.name)
def test_out_of_range_values_flagged_as_convert_does(sem: Sem) -> None:
    rng = random.Random(f"range {sem.name}")
    t = sem.spec.type
    dec = fastcdr.decoder(t)
    flagged = 0
    for _ in range(60):
        sample = random_sample(t, rng)
        _values_out_of_range(sample, rng)
        for v2, endian in encodings(sem):
            data = t.serialize(sample, use_version_2=v2, endianness=endian)
            got, ref = dec.json(data), to_json(t.deserialize(data))
            assert same(got[0], ref[0]) and got[1] == ref[1]
            flagged += bool(got[1])
    assert flagged


def test_unknown_enum_ordinal_and_too_many_satellites() -> None:
    """An ordinal no enum member has, and more than MAX_SATELLITES satellites: the same JSON and
    messages as convert (the first MAX kept, the elements past it not flagged)."""
    from UMAA.SEM.GPSStatus import GPSReportType, GPSSatelliteType

    rng = random.Random(7)
    sample = random_sample(GPSReportType, rng)
    sample.satellites = [random_sample(GPSSatelliteType, rng, absent=0.0) for _ in range(300)]
    for s in sample.satellites[250:]:
        s.azimuth = math.nan
    data = GPSReportType.serialize(sample, use_version_2=True)
    got, ref = fastcdr.decoder(GPSReportType).json(data), to_json(GPSReportType.deserialize(data))
    assert got == ref
    assert len(got[0]["satellites"]) == fastcdr.MAX_ELEMENTS and "satellites: 300 elements" in got[1][0]
    nan = [m.split(".")[0] for m in got[1] if m.endswith("azimuth: nan is not a number")]
    assert nan == [f"satellites[{i}]" for i in range(250, fastcdr.MAX_ELEMENTS)]

    ins = Sem.INS_REPORT.spec.type
    data = bytearray(ins.serialize(random_sample(ins, rng), use_version_2=False))
    struct.pack_into("<I", data, 4, 4242)  # state: the first member
    got = fastcdr.decoder(ins).json(bytes(data))
    assert got == to_json(ins.deserialize(bytes(data)))
    assert got[0]["state"] is None and got[1] == ["state: unknown InertialSensorStateEnumType ordinal 4242"]
    assert fastcdr.decoder(ins).sample(bytes(data)) == ins.deserialize(bytes(data))


def _mutations(data: bytes, rng: random.Random) -> list[bytes]:
    out = [
        data[:n]
        for n in sorted({0, 1, 2, 3, 4, 5, len(data) // 2, len(data) - 1, *rng.sample(range(len(data)), min(8, len(data)))})
    ]
    for _ in range(25):
        b = bytearray(data)
        for _ in range(rng.randrange(1, 4)):
            i = rng.randrange(4, len(b)) if len(b) > 4 else 0
            b[i] = rng.choice([0, 1, 0x7F, 0x80, 0xFF, rng.randrange(256)])
        out.append(bytes(b))
    for _ in range(10):  # a length (string, sequence, DHEADER) made huge or off by a little
        b = bytearray(data)
        i = rng.randrange(4, max(5, len(b) - 4)) & ~3
        if i + 4 <= len(b):
            struct.pack_into("<I", b, i, rng.choice([0xFFFFFFFF, 0x7FFFFFFF, len(b), struct.unpack_from("<I", b, i)[0] + 1]))
        out.append(bytes(b))
    return out


@pytest.mark.parametrize("sem", SEMS, ids=[s.name for s in SEMS])
def test_malformed_samples_raise_or_match_cyclonedds(sem: Sem) -> None:
    """Cut short, bytes flipped, lengths past the end: the generated decoder either raises (the Decoder
    counts that) or returns exactly what cyclonedds returns for the same bytes; it never returns
    something cyclonedds would not."""
    rng = random.Random(f"fuzz {sem.name}")
    t = sem.spec.type
    dec = fastcdr.decoder(t)
    decoded = refused = 0
    for data in encoded(sem, rng, 30):
        for bad in _mutations(data, rng):
            try:
                got = dec.sample(bad)
            except Exception:
                refused += 1
                continue
            decoded += 1
            try:
                ref = t.deserialize(bad)
            except Exception as e:  # pragma: no cover - a failure message
                pytest.fail(f"fastcdr decoded what cyclonedds refuses ({e}): {bad.hex()}")
            assert same(got, ref), bad.hex()
            got_json = dec.json(bad)
            ref_json = to_json(ref)
            assert same(got_json[0], ref_json[0]) and got_json[1] == ref_json[1], bad.hex()
    assert decoded and refused


@pytest.mark.parametrize("sem", [s for s in SEMS if s.spec.cls.value != "command"], ids=lambda s: s.name)
def test_decoder_counts_and_drops_malformed_samples(sem: Sem) -> None:
    """Through `Decoder.decode`, the ingest and replay path: nothing raises, what cannot be decoded is counted."""
    rng = random.Random(f"decoder {sem.name}")
    d = Decoder()
    for data in encoded(sem, rng, 15):
        for bad in _mutations(data, rng):
            d.decode(sem, bad, True, InstanceState.Alive, 0.0)
            d.decode(sem, bad, True, InstanceState.Alive, 0.0, convert=False)
            d.decode(sem, bad, False, InstanceState.NotAliveDisposed, 0.0)
    assert d.undecodable.get(sem.spec.name)


@pytest.mark.parametrize("sem", [s for s in SEMS if s.spec.cls.value != "command"], ids=lambda s: s.name)
def test_decoder_items_match_cyclonedds(sem: Sem) -> None:
    """What `Decoder.decode` hands the console: a report's JSON is `to_json` of cyclonedds' sample (also
    when kept aside for a replay's rebuild, `convert=False`), a status or ack carries cyclonedds' sample."""
    rng = random.Random(f"items {sem.name}")
    d = Decoder()
    for data in encoded(sem, rng, 20):
        ref = sem.spec.type.deserialize(data)
        item = d.decode(sem, data, True, InstanceState.Alive, 1.5)
        assert item is not None and item.source.bytes == bytes(ref.source) and item.alive
        if sem in REPORT_TOPICS:
            assert (item.report, item.invalid) == to_json(ref) and item.received_at == 1.5
            kept = d.decode(sem, data, True, InstanceState.Alive, 1.5, convert=False)
            assert kept.report is None and Decoder.convert(kept).report == item.report
        else:
            assert item.sample == ref and item.session.bytes == bytes(ref.sessionID)
    assert not d.undecodable and d.decoded


def test_what_is_not_generated_is_decoded_by_cyclonedds() -> None:
    """An XCDR1 sample of a type with @optional members (Cyclone neither offers nor accepts one for these
    topics, but a file could hold one): not generated, decoded by cyclonedds, the same values."""
    t = Sem.GPS_REPORT.spec.type
    with pytest.raises(fastcdr.Unsupported):
        fastcdr.generate(t, False, True, True)
    data = t.serialize(random_sample(t, random.Random(3)), use_version_2=False)
    ref = t.deserialize(data)
    assert fastcdr.decoder(t).sample(data) == ref
    assert fastcdr.decoder(t).json(data) == to_json(ref)


@pytest.mark.parametrize("sem", [s for s in Sem if s.spec.appendable is not None], ids=lambda s: s.name)
def test_decoder_reads_an_appendable_writers_sample_with_the_appendable_copy(sem: Sem) -> None:
    """One reader per extensibility (docs/dds.md): an appendable writer's sample (D_CDR2 header, a DHEADER before
    each struct) is decoded with the topic's appendable copy, a final writer's with its final type; both give the
    same report. The path of the ingest and of a replay alike."""
    decoder = Decoder()
    for seed in range(20):
        final = random_sample(sem.spec.type, random.Random(seed))
        appendable = random_sample(sem.spec.appendable, random.Random(seed))  # the same values, the other type
        want = to_json(final)
        for data in (final.serialize(use_version_2=True), appendable.serialize(use_version_2=True)):
            item = decoder.decode(sem, data, True, InstanceState.Alive, 0.0)
            assert item is not None and (item.report, item.invalid) == want, (seed, data[:4].hex())
        assert appendable.serialize(use_version_2=True)[1] == 0x09 and final.serialize(use_version_2=True)[1] == 0x07
    assert decoder.undecodable == {}


LEARNING = [(s.spec.type, None) for s in SEMS if fastcdr.learnable(s.spec.type, True, True)] + [
    (s.spec.type, umaa_6_0.REPORTS[s])
    for s in Sem60
    if s in umaa_6_0.REPORTS and umaa_6_0.REPORTS[s].spec is not None and fastcdr.learnable(s.spec.type, True, True)
]


@pytest.mark.parametrize(("t", "report"), LEARNING, ids=[t.__name__ for t, _ in LEARNING])
def test_learned_presence_patterns_decode_as_cyclonedds(t: Any, report: Any) -> None:
    """A type of fixed-size members with @optional ones learns the presence patterns of the samples it reads (one
    unpack each after that); whichever pattern a sample has, learned or not, its JSON is cyclonedds' (a 6.0 report's
    adapted to the model), invalid values included."""
    rng = random.Random(t.__name__)
    dec = fastcdr.TypeDecoder(t) if report is None else fastcdr.TypeDecoder(t, report.spec, umaa_6_0.model_path, report.model)
    samples = [random_sample(t, rng, absent=(0.0, 1.0, 0.1, 0.5)[i % 4]) for i in range(40)]
    for i, sample in enumerate(samples * 3):
        if i % 7 == 0:
            _values_out_of_range(sample, rng)
        for endian in (Endianness.Little, Endianness.Big):
            data = t.serialize(sample, use_version_2=True, endianness=endian)
            ref = to_json(t.deserialize(data))
            assert same(dec.json(data), ref if report is None else report.model(*ref)), (i, data.hex())
    learned = dec.patterns
    assert learned and all(0 < len(p) <= fastcdr.PATTERNS_MAX for p in learned.values())


@pytest.mark.parametrize(("t", "report"), LEARNING, ids=[t.__name__ for t, _ in LEARNING])
def test_every_presence_pattern_learned_decodes_as_cyclonedds(t: Any, report: Any) -> None:
    """Whichever members a sample leaves out, the one unpack of its pattern once learned (adjacent absent members'
    presence flags tested as one integer, unused reads skipped as padding) reads every member at its offset: each
    pattern of many random samples, learned four at a time, gives cyclonedds' JSON for every sample, its own pattern
    or another's."""
    rng = random.Random(f"patterns {t.__name__}")
    samples = [random_sample(t, rng, absent=rng.random()) for _ in range(120)]
    for sample in samples[::5]:
        _values_out_of_range(sample, rng)
    spec, rename = (None, None) if report is None else (report.spec, umaa_6_0.model_path)
    for little, endian in ((True, Endianness.Little), (False, Endianness.Big)):
        datas = [t.serialize(sample, use_version_2=True, endianness=endian) for sample in samples]
        wants = [to_json(t.deserialize(data)) for data in datas]
        wants = wants if report is None else [report.model(*w) for w in wants]
        patterns: set[tuple[bool, ...]] = set()
        for data in datas:
            learner = fastcdr.TypeDecoder(t)
            learner.json(data)
            patterns.update(*learner.patterns.values())
        ordered = sorted(patterns)
        assert len(ordered) > 1
        for k in range(0, len(ordered), fastcdr.PATTERNS_MAX):
            source, ns = fastcdr.generate(t, True, little, True, spec, rename, tuple(ordered[k : k + fastcdr.PATTERNS_MAX]))
            exec(compile(source, "<patterns>", "exec"), ns)  # the generated decoder, as TypeDecoder builds it
            for data, want in zip(datas, wants, strict=True):
                got = ns["decode"](data)
                assert same(got[0], want[0]) and got[1] == want[1], (ordered[k : k + fastcdr.PATTERNS_MAX], data.hex())


def test_a_value_the_model_leaves_out_is_not_decoded() -> None:
    """A 6.0 report's source is an identifier whose parentID the model leaves out: no GUID text is made of it."""
    r = umaa_6_0.REPORTS[Sem60.INS_REPORT]
    source, _ = fastcdr.generate(Sem60.INS_REPORT.spec.type, False, True, True, r.spec, umaa_6_0.model_path)
    assert source.count("guid_text(") == 1


def test_a_read_the_model_leaves_out_makes_no_value() -> None:
    """The parentID of a 6.0 report's source is read as padding (no bytes object made for it), in the learned pattern's
    one unpack as member by member."""
    r = umaa_6_0.REPORTS[Sem60.GLOBAL_POSE_REPORT]
    t = Sem60.GLOBAL_POSE_REPORT.spec.type
    pattern = (False,) * 4 + (False, True, False)  # no altitudes, no attitude covariance, depth, no position covariance
    _, ns = fastcdr.generate(t, True, True, True, r.spec, umaa_6_0.model_path, (pattern,))
    formats = [s.format for s in ns.values() if isinstance(s, struct.Struct)]
    assert sum(f.count("16s") for f in formats) == 2  # the source's id, in the pattern's unpack and member by member
    assert sum(f.count("16x") for f in formats) == 2  # its parentID


def test_adjacent_absent_members_are_one_test() -> None:
    """A learned pattern checks the presence flags of adjacent absent members (GlobalPose's four altitudes) as one
    integer: one test, not four."""
    r = umaa_6_0.REPORTS[Sem60.GLOBAL_POSE_REPORT]
    pattern = (False,) * 4 + (False, True, False)
    source, _ = fastcdr.generate(Sem60.GLOBAL_POSE_REPORT.spec.type, True, True, True, r.spec, umaa_6_0.model_path, (pattern,))
    condition = next(line for line in source.splitlines() if line.strip().startswith("if ") and " and " in line)
    assert condition.count("not ") == 3 and condition.count(" and ") == 3, condition


def test_each_versions_satellites_keep_their_own_bound() -> None:
    """A 6.0 GPSReport keeps its 300 satellites (its type bounds them at 300); a 301st (which no 6.0 writer may send,
    made here by hand) is cut and said, as 3.0.1's unbounded satellites are past the console's 256; the 6.0 model's
    report keeps the 300 too. The generated decoder and convert agree."""
    from sem_console.codec.decode import report_json

    t = Sem60.GPS_REPORT.spec.type
    rng = random.Random(300)
    sample = random_sample(t, rng)
    one = random_sample(_satellite_type(t), rng, absent=0.0)
    sample.satellites = [one] * 299
    fewer = t.serialize(sample, use_version_2=False)
    sample.satellites = [one] * 300
    full = t.serialize(sample, use_version_2=False)
    size = len(full) - len(fewer)  # one satellite (its size a multiple of its alignment)
    at = next(k for k in range(len(full)) if full[k] != fewer[k])  # the count
    assert struct.unpack_from("<I", full, at)[0] == 300
    over = full[:at] + struct.pack("<I", 301) + full[at + 4 : at + 4 + size] + full[at + 4 :]
    for data, kept, said in ((full, 300, []), (over, 300, ["satellites: 301 elements, more than 300; the first 300 kept"])):
        got, ref = fastcdr.decoder(t).json(data), to_json(t.deserialize(data))
        assert got == ref
        assert len(got[0]["satellites"]) == kept and [m for m in got[1] if "elements" in m] == said
        model, invalid = report_json(Sem60.GPS_REPORT)(data)
        assert len(model["satellites"]) == kept and [m for m in invalid if "elements" in m] == said


def _satellite_type(t: Any) -> Any:
    import typing

    return typing.get_args(typing.get_args(typing.get_type_hints(t, include_extras=True)["satellites"])[0])[0]


def test_a_vehicles_parent_is_the_one_its_latest_report_says() -> None:
    """The parent a 6.0 vehicle's reports give its source (a command's destination carries it): learned from its first
    report, and learned again when it is given another parent, or when it spoke 3.0.1 (no parent) before."""
    import uuid

    from sem_console.versions.umaa_6_0 import identifier

    vehicle, first, second = uuid.uuid4(), uuid.uuid4(), uuid.uuid4()
    d = Decoder()
    old = random_sample(Sem.INS_REPORT.spec.type, random.Random(1))
    old.source = list(vehicle.bytes)
    item = d.decode(Sem.INS_REPORT, Sem.INS_REPORT.spec.type.serialize(old), True, InstanceState.Alive, 0.0)
    assert item is not None and item.source == vehicle and item.parent is None
    for sem in (Sem60.INS_REPORT, Sem60.GPS_REPORT):
        t = sem.spec.type
        for parent in (first, first, second, second, first):
            sample = random_sample(t, random.Random(str(parent)))
            sample.source = identifier(vehicle, parent)
            item = d.decode(sem, t.serialize(sample), True, InstanceState.Alive, 0.0)
            assert item is not None and item.source == vehicle and item.parent == parent, (sem.name, parent)
