"""RTI Connext, through its Python Connector, as the other vendor in interoperability tests.

The participant keeps RTI's defaults for everything about types and encoding: the types come
from the project's IDL as RTI's XML type representation (`idl2xml`), with no extensibility
given (RTI applies appendable), and no data representation set (RTI writers and readers use
XCDR1 only). What is set: UDPv4 on loopback with 127.0.0.1 as the initial peer (Cyclone speaks
neither RTI's shared memory nor multicast on `lo`), and per topic class the reliability,
durability and depth a UMAA system configures; and the database's shutdown cleanup period cut
to 10 ms (Connext 6.1.2's default made every participant's deletion take 2.2 s, a test's teardown;
it only paces the clean-up at deletion). Command writers serialize the key with a dispose,
so a cancel carries the instance's key and not only its MD5 key hash (keys over 16 bytes).
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path
from typing import Any
from xml.sax.saxutils import quoteattr

import rticonnextdds_connector as rti

from sem_console.dds.qos import TopicClass
from sem_console.dds.topics import AnySem, Sem, Sem60

from .idl2xml import IDL_ROOT, types_xml

RECIPE_XML = Path(__file__).resolve().parents[4] / "docs" / "rti" / "sem-console-interop.xml"
RECIPE_ENV = {"NDDS_XTYPES_COMPLIANCE_MASK": "0x1a9"}
# UMAA 6.0: the QoS of RTI's UMAA kit (UMAAQoSLib, as qos/umaa_qos_lib.xml there sets it; our own file of the same
# settings) and the project's drop-in for a vehicle on it
UMAA_QOS_XML = Path(__file__).resolve().parent / "umaa-qos-lib.xml"
UMAA_60_XML = RECIPE_XML.parent / "umaa-6.0-interop.xml"


_DEPTH = {TopicClass.COMMAND: 1, TopicClass.STATUS: 32, TopicClass.REPORT: 1}


def type_name(sem: AnySem) -> str:
    return sem.spec.type.__idl_typename__.replace(".", "::")


def _short(sem: AnySem) -> str:
    return type_name(sem).rsplit("::", 1)[1]


def sem_key(sem: AnySem) -> str:
    """A topic's name across the worker's pipe: its table and member ("Sem60.GPS_REPORT")."""
    return f"{type(sem).__name__}.{sem.name}"


def sem_of(key: str) -> AnySem:
    table, name = key.split(".")
    return {"Sem": Sem, "Sem60": Sem60}[table][name]  # type: ignore[return-value]


def _idl_root(sems: list[AnySem]) -> Path:
    """The IDL tree of the participant's UMAA version (one per participant: the two name their types alike)."""
    versions = {isinstance(s, Sem60) for s in sems}
    if len(versions) > 1:
        raise ValueError("an RTI participant holds the topics of one UMAA version")
    return IDL_ROOT / "umaa-6.0" if versions == {True} else IDL_ROOT


def _endpoint_qos(
    sem: AnySem, writer: bool, representation: str | None = None, recipe: str | None = None, umaa: str | None = None
) -> str:
    tag = "datawriter_qos" if writer else "datareader_qos"
    extra = ""
    if representation:
        extra += f"<representation><value><element>{representation}</element></value></representation>"
    if umaa is not None:  # the UMAA kit's QoS, assigned by topic name as its AssignerQoS does (rti/umaa-qos-lib.xml)
        return f'<{tag} base_name={quoteattr(umaa)}>{extra}</{tag}>'
    if writer and sem.spec.cls is TopicClass.COMMAND and recipe is None:
        # on RTI's defaults a dispose carries only the key hash, which Cyclone cannot use for a command's key (the
        # drop-in's profiles set this for every writer; with a recipe the tests take it from there)
        extra += "<protocol><serialize_key_with_dispose>true</serialize_key_with_dispose></protocol>"
    # Unbounded members (GPSReport's satellites): RTI allocates the largest sample up front unless
    # told to allocate samples over this size on demand.
    side = "writer" if writer else "reader"
    extra += (
        f"<property><value><element><name>dds.data_{side}.history.memory_manager.fast_pool.pool_buffer_max_size"
        "</name><value>4096</value></element></value></property>"
    )
    if writer:
        extra += (
            "<writer_data_lifecycle><autodispose_unregistered_instances>false</autodispose_unregistered_instances>"
            "</writer_data_lifecycle>"
        )
    base = ' base_name="SemInterop::Loopback"'
    return (
        f'<{tag}{base}><reliability><kind>RELIABLE_RELIABILITY_QOS</kind></reliability>'
        f'<durability><kind>TRANSIENT_LOCAL_DURABILITY_QOS</kind></durability>'
        f'<history><kind>KEEP_LAST_HISTORY_QOS</kind><depth>{_DEPTH[sem.spec.cls]}</depth></history>{extra}</{tag}>'
    )


def config_xml(
    domain: int,
    writers: list[AnySem],
    readers: list[AnySem],
    representation: str | None = None,
    extensibility: str | None = None,
    recipe: str | None = None,
    type_object_max: int | None = None,
    partition: str | None = None,
    name: str = "Rti",
    umaa: tuple[str, str] | None = None,
) -> str:
    """RTI's XML for one participant. ``partition``: its publisher's and subscriber's; ``recipe``: the profile of the
    repository's drop-in (docs/rti/sem-console-interop.xml, "Default" or "AppendableGps", loaded beside this XML as the
    file it is) its QoS inherits; ``type_object_max``: RTI's type_object_max_serialized_length; ``name``: the
    participant's, as discovery shows it; ``umaa``: the profiles (participant, endpoints) a vehicle on RTI's UMAA kit
    takes its QoS from (rti/umaa-qos-lib.xml and the drop-in docs/rti/umaa-6.0-interop.xml, loaded beside this XML),
    instead of the project's QoS per topic class. The types are those of the topics' UMAA version."""
    sems = list(dict.fromkeys(writers + readers))
    # registered under the type's full name; the XML name is the short one, as RTI's UMAA kit has it (a UMAA 6.0 topic
    # is named after its type, and XML does not take two objects of one name)
    regs = "".join(
        f"<register_type name={quoteattr(_short(s))} type_ref={quoteattr(type_name(s))}>"
        f"<registered_name>{type_name(s)}</registered_name></register_type>"
        for s in sems
    )
    topics = "".join(f"<topic name={quoteattr(s.spec.name)} register_type_ref={quoteattr(_short(s))}/>" for s in sems)
    pubs = "".join(
        f"<data_writer name={quoteattr(s.name)} topic_ref={quoteattr(s.spec.name)}>"
        f"{_endpoint_qos(s, True, representation, recipe, umaa and umaa[1])}</data_writer>"
        for s in writers
    )
    subs = "".join(
        f"<data_reader name={quoteattr(s.name)} topic_ref={quoteattr(s.spec.name)}>"
        f"{_endpoint_qos(s, False, representation, recipe, umaa and umaa[1])}</data_reader>"
        for s in readers
    )
    base = f' base_name="SemConsoleInterop::{recipe}"' if recipe else f" base_name={quoteattr(umaa[0])}" if umaa else ""
    in_partition = f"<partition><name><element>{partition}</element></name></partition>"
    pub_qos, sub_qos = (
        (f"<publisher_qos>{in_partition}</publisher_qos>", f"<subscriber_qos>{in_partition}</subscriber_qos>")
        if partition is not None
        else ("", "")
    )
    limits = (
        ""
        if type_object_max is None
        else (
            f"<resource_limits><type_object_max_serialized_length>{type_object_max}"
            "</type_object_max_serialized_length></resource_limits>"
        )
    )
    return f"""<?xml version="1.0"?>
<dds>
<qos_library name="SemInterop"><qos_profile name="Loopback" is_default_qos="true"{base}>
<domain_participant_qos>{limits}
  <database><shutdown_cleanup_period><sec>0</sec><nanosec>10000000</nanosec></shutdown_cleanup_period></database>
  <transport_builtin><mask>UDPv4</mask></transport_builtin>
  <discovery><initial_peers><element>32@udpv4://127.0.0.1</element></initial_peers><multicast_receive_addresses/></discovery>
</domain_participant_qos>
</qos_profile></qos_library>
{types_xml(_idl_root(sems), extensibility=extensibility)}
<domain_library name="Domains"><domain name="Sem" domain_id="{domain}">{regs}{topics}</domain></domain_library>
<domain_participant_library name="Participants"><domain_participant name={quoteattr(name)} domain_ref="Domains::Sem">
<publisher name="pub">{pub_qos}{pubs}</publisher><subscriber name="sub">{sub_qos}{subs}</subscriber>
</domain_participant></domain_participant_library>
</dds>"""


class RtiParticipant:
    """One RTI Connext participant with a writer and/or reader per given SEM topic."""

    def __init__(
        self,
        domain: int,
        writers: list[AnySem] = (),
        readers: list[AnySem] = (),  # type: ignore[assignment]
        representation: str | None = None,
        extensibility: str | None = None,
        recipe: str | None = None,
        type_object_max: int | None = None,
        partition: str | None = None,
        name: str = "Rti",
        umaa: tuple[str, str] | None = None,
    ) -> None:
        with tempfile.NamedTemporaryFile("w", suffix=".xml", delete=False) as f:  # removed in close()
            f.write(
                config_xml(
                    domain,
                    list(writers),
                    list(readers),
                    representation,
                    extensibility,
                    recipe,
                    type_object_max,
                    partition,
                    name,
                    umaa,
                )
            )
        self._file = f
        # the drop-ins as an RTI user loads them: the files themselves, first of an RTI URL group (files separated by ';')
        first = [RECIPE_XML] if recipe else [UMAA_QOS_XML, UMAA_60_XML] if umaa else []
        url = ";".join([*map(str, first), self._file.name])
        self.connector = rti.Connector(f"Participants::{name}", url)
        self.outputs = {s: self.connector.get_output(f"pub::{s.name}") for s in writers}
        self.inputs = {s: self.connector.get_input(f"sub::{s.name}") for s in readers}

    def wait_matched(self, sem: AnySem, timeout: float = 30.0) -> None:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            port = self.outputs.get(sem) or self.inputs[sem]
            matched = port.matched_subscriptions if sem in self.outputs else port.matched_publications
            if matched:
                return
            time.sleep(0.05)
        raise TimeoutError(f"RTI {sem.spec.name} matched nothing")

    @property
    def writers(self) -> set[AnySem]:
        return set(self.outputs)

    @property
    def version(self) -> str:
        """The Connext core's build, e.g. NDDSCORE_BUILD_7.7.0.0_…"""
        return next(line for line in rti.Connector.get_version().splitlines() if line.startswith("NDDSCORE"))

    def matched(self, sem: AnySem, writer: bool) -> list[Any]:
        return list(self.outputs[sem].matched_subscriptions if writer else self.inputs[sem].matched_publications)

    def write(self, sem: AnySem, sample: dict[str, Any], action: str = "write") -> None:
        out = self.outputs[sem]
        out.clear_members()
        out.instance.set_dictionary(sample)
        out.write(**({"action": action} if action != "write" else {}))

    def take(self, sem: AnySem) -> list[tuple[dict[str, Any] | None, str]]:
        """(sample or None for a dispose, instance state) for each sample RTI's reader has."""
        inp = self.inputs[sem]
        inp.take()
        out = []
        for s in inp.samples:
            state = s.info["instance_state"]
            out.append((s.get_dictionary() if s.valid_data else None, state))
        return out

    def take_with_keys(self, sem: AnySem) -> list[tuple[dict[str, Any], str, bool]]:
        """(sample, instance state, valid data) for each sample RTI's reader has; a dispose (not valid data) as the
        members RTI has of it: its key members as the dispose carried them, the others zero."""
        inp = self.inputs[sem]
        inp.take()
        return [(s.get_dictionary(), s.info["instance_state"], s.valid_data) for s in inp.samples]

    def close(self) -> None:
        self.connector.close()
        Path(self._file.name).unlink(missing_ok=True)
