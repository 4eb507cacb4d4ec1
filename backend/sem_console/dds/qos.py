"""QoS per topic class: the one place that decides how SEM topics behave on the bus.

| class    | topics                            | reliability | durability      | history      |
|----------|-----------------------------------|-------------|-----------------|--------------|
| command  | *Command                          | reliable    | transient-local | keep last 1  |
| status   | *CommandStatus, *CommandAckReport | reliable    | transient-local | keep last 32 |
| report   | *Report (GPS, GPSFix, INS)        | reliable    | transient-local | keep last 1  |

Why: a command is immutable, one sample per sessionID; a provider that starts or restarts later still finds it
(ICD 4.1.2). Every status transition reaches a running consumer in order (a command has at most 5), and a consumer
that joins late sees where each command stands. A consumer that starts after the provider shows the last report at
once; newer reports replace older ones.

UMAA 6.0 mandates no QoS. Its command, status and ack topics take RTI's UMAAQoSLib CommandQoS (the de facto
reference, `qos/umaa_qos_lib.xml` of RTI's UMAA kit) over the classes above (`umaa_command_qos`): keep-all history,
and the writer's liveliness automatic with a 5 s lease. Reliability and transient-local durability stay, as the 3.0.1
ICD asks (a provider that starts later still finds the command). Readers request no liveliness (RTI's reader asks 10 s,
which a writer of any shorter lease meets), so they match any writer.

The data representation follows from the type, not the topic (`representation`): a type with
no @optional member travels in XCDR1, which every vendor's default reader accepts (RTI
Connext's accepts nothing else); a type with @optional members travels in XCDR2 only, because
vendors disagree on XCDR1's layout of an optional member (README, "Other DDS vendors"): an
XCDR1 sample of such a type is misread or rejected across vendors, so it is neither written
nor accepted.
"""

from __future__ import annotations

from enum import Enum

from cyclonedds.core import Policy, Qos
from cyclonedds.util import duration

STATUS_DEPTH = 32
_RELIABLE = Policy.Reliability.Reliable(duration(seconds=1))


class TopicClass(str, Enum):
    COMMAND = "command"
    STATUS = "status"
    REPORT = "report"


_DEPTH = {TopicClass.COMMAND: 1, TopicClass.STATUS: STATUS_DEPTH, TopicClass.REPORT: 1}


def writer_qos(cls: TopicClass) -> Qos:
    return Qos(
        _RELIABLE,
        Policy.Durability.TransientLocal,
        Policy.History.KeepLast(_DEPTH[cls]),
        # Instances end by an explicit dispose (cancel, cleanup, shutdown), never by a writer closing.
        Policy.WriterDataLifecycle(autodispose=False),
    )


# What a publisher of the console's offers: TOPIC presentation with ordered access, which a subscriber of RTI's UMAA kit
# requests (its participant profile asks it of every subscriber, for the ICDs' ordering across a topic's instances); a
# publisher offering less (DDS's default, INSTANCE) is not matched by its readers. A writer sends its samples in the
# order written, and one publisher of ours holds one writer per topic, so the offer is kept; readers asking less match.
PUBLISHER = Qos(Policy.PresentationAccessScope.Topic(coherent_access=False, ordered_access=True))


_LEASE = duration(seconds=5)


def umaa_command_qos(writer: bool) -> Qos:
    """RTI UMAAQoSLib's CommandQoS as taken over on a UMAA 6.0 command, status and ack topic (the module docstring)."""
    if writer:
        return Qos(Policy.History.KeepAll, Policy.Liveliness.Automatic(lease_duration=_LEASE))
    return Qos(Policy.History.KeepAll)


def representation(xcdr2_only: bool, writer: bool) -> Qos:
    """The DataRepresentation of an endpoint: XCDR2 only for types with @optional members; otherwise
    writers offer XCDR1 and readers accept XCDR1 and XCDR2."""
    if xcdr2_only:
        return Qos(Policy.DataRepresentation(use_xcdrv2_representation=True))
    return Qos(Policy.DataRepresentation(use_cdrv0_representation=True, use_xcdrv2_representation=not writer))


# A reader's latency budget must be at least the writer's for them to match: ours accept any.
_ANY_LATENCY = Policy.LatencyBudget(duration(infinite=True))


def reader_qos(cls: TopicClass, durable: bool = True) -> Qos:
    """Reliable; transient-local (what a writer published before the reader started), or
    volatile with `durable=False` (the reliable reader that also matches a volatile writer)."""
    return Qos(
        _RELIABLE,
        Policy.Durability.TransientLocal if durable else Policy.Durability.Volatile,
        Policy.History.KeepLast(_DEPTH[cls]),
        _ANY_LATENCY,
        Policy.DataRepresentation(use_cdrv0_representation=True, use_xcdrv2_representation=True),
    )


def any_writer_reader_qos(cls: TopicClass) -> Qos:
    """Best-effort, volatile, any latency budget: matches a writer whatever it offers.

    A console reads each report, status and ack topic with this reader and with both
    `reader_qos` readers, and applies each writer's samples from the most reliable of the
    three that matches it (`console.ingest`).
    """
    return Qos(
        Policy.Reliability.BestEffort,
        Policy.Durability.Volatile,
        Policy.History.KeepLast(_DEPTH[cls]),
        _ANY_LATENCY,
        Policy.DataRepresentation(use_cdrv0_representation=True, use_xcdrv2_representation=True),
    )
