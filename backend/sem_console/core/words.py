"""The operator's words: one name for each state, reason and alarm kind the console shows, wherever it shows it.

One table for the backend and the dashboard. The backend composes its alarm texts from it (`console/alarms.py`); the
dashboard reads it as `frontend/schema/words.json` (written by `python -m sem_console.schema_export`, kept current by
`tests/unit/test_schema_export.py`) through `frontend/src/lib/labels.ts`, for the fleet bar, the vehicle list and the panels.
Wherever a word is shown, its literal (the UMAA one, for the engineer comparing the screen with a log) is in a tooltip.

A word is written as it starts a line ("Operational"); the places that put it inside a phrase lower its first letter
(`inline`): "INS operational", "Alpha: link lost".

To add a state, a reason or an alarm kind, add its entry here and run `python -m sem_console.schema_export`:
`tests/system/test_words.py` fails for a literal of a UMAA enumeration the console shows, or of any enumeration of its published
schemas (an alarm kind, a link, a task state...) that has no words here; a new enumeration there must be named in it,
with its table or as no state the console names.
"""

from __future__ import annotations

from typing import Final

WORDS: Final[dict[str, dict[str, str]]] = {
    # ---- UMAA enumerations (UMAA::Common::MaritimeEnumeration), every literal ----
    # GPSFixReport.GPSFixCommandStatus: the receiver's own state, reported whether or not a fix was commanded
    "GPSFixEnumType": {"INITIATING": "Initiating a fix", "PERFORMING": "Performing a fix", "STABLE": "Fix stable"},
    "GPSNavigationSolutionEnumType": {
        "GPS_1": "GPS, 1 satellite",
        "GPS_2": "GPS, 2 satellites",
        "GPS_2D": "GPS 2D",
        "GPS_3": "GPS, 3 satellites",
        "GPS_3D": "GPS 3D",
        "GPS_4": "GPS, 4 satellites",
        "GPS_DEAD_RECK": "Dead reckoning",
        "NO_NAV": "No navigation",
    },
    "GPSConstellationEnumType": {
        "UNKNOWN": "Unknown",
        "BEIDOU": "BeiDou",
        "GALILEO": "Galileo",
        "GLONASS": "GLONASS",
        "GPS": "GPS",
        "IRNSS": "NavIC",
        "QZSS": "QZSS",
        "SBAS": "SBAS",
    },
    "InertialSensorStateEnumType": {"OFF": "Off", "ON": "On", "RESTARTING": "Restarting"},
    "InertialSensorOpStatusEnumType": {
        "INIT": "Starting up",
        "COURSE_STATIONARY_ALIGNMENT": "Coarse alignment, stationary",
        "COURSE_GPS_ALIGNMENT": "Coarse alignment, GPS-aided",
        "FINE_STATIONARY_ALIGNMENT_STARTED": "Fine alignment, stationary",
        "FINE_GPS_ALIGNMENT_STARTED": "Fine alignment, GPS-aided",
        "FINE_STATIONARY_ALIGNMENT_COMPLETE": "Fine alignment done, stationary",
        "FINE_GPS_ALIGNMENT_COMPLETE": "Fine alignment done, GPS-aided",
        "OPERATIONAL": "Operational",
        "INERTIAL_SENSOR_FAILURE": "Failed",
        # ---- UMAA 6.0's INS statuses: the stage of each kind of alignment, or its failure (6.0 spells coarse
        # "COARSE"; it has no OPERATIONAL: an aligned 6.0 INS reports the completed stage) ----
        "COARSE_STATIONARY_ALIGNMENT": "Coarse alignment, stationary",
        "COARSE_GPS_ALIGNMENT": "Coarse alignment, GPS-aided",
        "COARSE_BEST_ALIGNMENT": "Coarse alignment, best available",
        "COARSE_TRANSFER_ALIGNMENT": "Coarse alignment, transfer",
        "FINE_BEST_ALIGNMENT_STARTED": "Fine alignment, best available",
        "FINE_TRANSFER_ALIGNMENT_STARTED": "Fine alignment, transfer",
        "FINE_BEST_ALIGNMENT_COMPLETE": "Fine alignment done, best available",
        "FINE_TRANSFER_ALIGNMENT_COMPLETE": "Fine alignment done, transfer",
        "SNAP_ALIGNMENT_COMPLETE": "Snap alignment done",
        "STATIONARY_ALIGNMENT_FAILURE": "Stationary alignment failed",
        "GPS_ALIGNMENT_FAILURE": "GPS-aided alignment failed",
        "BEST_ALIGNMENT_FAILURE": "Best available alignment failed",
        "TRANSFER_ALIGNMENT_FAILURE": "Transfer alignment failed",
        "SNAP_ALIGNMENT_FAILURE": "Snap alignment failed",
    },
    # ---- UMAA 6.0's position and clock (GlobalPoseReportType.navigationSolution, GPSClockType.timeFigureOfMerit) ----
    # whether the position is measured or estimated (a 3.0.1 vehicle says it as GPSLatLongValid: GPS or INS position)
    "NavigationSolutionEnumType": {
        "MEASURED": "Measured position",
        "ESTIMATED": "Estimated position",
        "GROUND_TRUTH": "Ground truth position",
    },
    # the time's estimated error to UTC (1 sigma), in the classes the figure of merit names
    "TFOMEnumType": {
        "TFOM_1": "Time within 1 ns",
        "TFOM_2": "Time within 10 ns",
        "TFOM_3": "Time within 100 ns",
        "TFOM_4": "Time within 1 µs",
        "TFOM_5": "Time within 10 µs",
        "TFOM_6": "Time within 100 µs",
        "TFOM_7": "Time within 1 ms",
        "TFOM_8": "Time within 10 ms",
        "TFOM_9": "Time off by over 10 ms",
    },
    # the INS panel's alignment steps: the stages of the kind of alignment its status names (the status says which);
    # DONE: the alignment complete (a 3.0.1 INS then reports OPERATIONAL; a 6.0 INS has no OPERATIONAL)
    "insAlignmentStep": {
        "INIT": "Starting up",
        "COARSE": "Coarse alignment",
        "FINE": "Fine alignment",
        "DONE": "Alignment done",
        "OPERATIONAL": "Operational",
    },
    "CommandStatusEnumType": {
        "ISSUED": "Received",
        "COMMANDED": "Accepted",
        "EXECUTING": "In progress",
        "COMPLETED": "Completed",
        "FAILED": "Failed",
        "CANCELED": "Cancelled",
    },
    # a command's status reason, said after its status: "Failed: the equipment failed"
    "CommandStatusReasonEnumType": {
        "SUCCEEDED": "Succeeded",
        "CANCELED": "On request",
        "VALIDATION_FAILED": "The vehicle found the request invalid",
        "OBJECTIVE_FAILED": "The goal could not be reached",
        "SERVICE_FAILED": "The vehicle's service failed",
        "RESOURCE_FAILED": "The equipment failed",
        "RESOURCE_REJECTED": "The vehicle refused it",
        "INTERRUPTED": "Another command took over",
        "TIMEOUT": "Timed out",
        # UMAA 6.0 (its ICD 4.1.4.2): the consumer sent the command again, newer; the vehicle starts it over, ISSUED:
        # "Received again, updated: it starts over"
        "UPDATED": "Again, updated: it starts over",
    },
    # ---- UMAA 6.0 commanding ----
    # InertialSensorCommandType.state: the alignment (or start-up) the operator asks of a UMAA 6.0 inertial sensor
    "InertialSensorCmdEnumType": {
        "BEST_ALIGN": "Best alignment available",
        "GPS_ALIGN": "GPS-aided alignment",
        "INIT": "Initialise",
        "SNAP_ALIGN": "Snap alignment",
        "STATIONARY_ALIGN": "Stationary alignment",
        "TRANSFER_ALIGN": "Transfer alignment",
    },
    # ---- the console's own states ----
    # a command the vehicle has not acknowledged (no ISSUED) within the unanswered timeout
    "command": {"unanswered": "No answer"},
    # why a command was cancelled (`Command.cancelCause`): an operator asked it, or its station's shutdown cancelled what
    # it had running
    "cancelCause": {"operator": "Cancel asked", "shutdown": "Station stopped"},
    # the link to a vehicle and the freshness of its data (`Provider.link`; the dashboard's "stale": live but silent a
    # few seconds, and "unreachable": the page no longer hears the console, so nothing it shows is current; "planned":
    # lost during the vehicle's planned silence, expected: "Out of comms (planned) until 14:20")
    "link": {
        "live": "Live",
        "regained": "Regained",
        "stale": "Stale",
        "lost": "Lost",
        "unreachable": "Not updating",
        "planned": "Out of comms (planned)",
        # silent while this console is behind (console/load.py): its silence may be the console's, so not judged
        "unchecked": "Not checked: console behind",
    },
    # the fleet's exceptional vehicles besides the lost, as the fleet bar counts them and the vehicle list filters them
    # ("2 in alarm": vehicles with an unacknowledged alarm; "1 commanded": vehicles with a command in progress)
    "fleet": {"alarm": "In alarm", "commanded": "Commanded"},
    # a vehicle seen through a sem-relay (`ProviderSummary.relay`): `{relay}` its --name, `{age}` how old its newest
    # data is by its own time stamp ("1.4 s"): "via relay ship-1, 1.4 s old"; unknown: no time stamp of it yet
    "relay": {
        "via": "Via relay {relay}, {age} old",
        "unknown": "Via relay {relay}",
        "title": "Seen through sem-relay {relay}, of the vehicles' side; the age: of its newest data, by its own time stamp",
    },
    # GPSFixStatusReport.fixValid
    "fixValid": {"true": "Fix valid", "false": "No fix"},
    # a vehicle whose UMAA version has no GPS fix service (6.0): it reports no fix status; how good its position is, its
    # navigation solution says (GlobalPoseReportType.navigationSolution: "Position quality: measured position")
    "fixService": {"none": "No fix service", "quality": "Position quality"},
    # what a vehicle's UMAA version never reports, said once where its rows are left out: `{version}` "6.0", `{members}`
    # "SOG, magnetic variation, velocity": "Not in UMAA 6.0: SOG, magnetic variation, velocity"
    "notInVersion": {"members": "Not in UMAA {version}: {members}"},
    # GPSFixReport.GPSLatLongValid: whether the position is the receiver's, else the INS's
    "GPSLatLongValid": {"true": "GPS position", "false": "INS position"},
    # the alarm kinds (`api.schemas.AlarmKind`): what the alarm is about, as a heading ("Link lost: 20 vehicles")
    "alarmKind": {
        "link-lost": "Link lost",
        "ins-failure": "INS failed",
        "fix-lost": "GPS fix lost",
        "no-fix-after-command": "No GPS fix after a fix command",
        "command-unanswered": "Command unanswered",
        "command-failed": "Command failed",
        "command-interrupted": "Command interrupted",
        "flow-violation": "Invalid status sequence",
        "executed-late": "Command executed late",
        "recording-failed": "Recording failed",
        "silence-overdue": "Not heard after a planned silence",
        "relay-silent": "Relay silent",
        "console-overloaded": "Console overloaded",
    },
    # the sentence of an alarm kind whose text says more than its state, by kind; `{until}` "14:20 UTC" (its date when
    # not today's), `{grace}` seconds: "Charlie: not heard by 14:20 UTC, the end of its planned silence (30 s grace)"
    "alarmText": {
        "silence-overdue": "Not heard by {until}, the end of its planned silence ({grace} s grace)",
        # `{relay}` the relay's --name, `{vehicles}` "12 vehicles": "relay ship-1 silent: 12 vehicles"
        "relay-silent": "Relay {relay} silent: {vehicles}",
        # `{delay}` "3.2 s" (the worst of its delays), `{vehicles}` "12 vehicles"
        "console-overloaded": "This console is overloaded: it ran up to {delay} behind and did not check {vehicles} (no "
        "link-lost alarm for a silence its delay may explain); run fewer vehicles on this console or give it a bigger "
        "machine",
    },
    # an alarm's severity and its ISA-18.2 state (`api.schemas.Alarm`)
    "alarmSeverity": {"alarm": "Alarm", "warning": "Warning"},
    "alarmState": {
        "active-unacknowledged": "Unacknowledged",
        "active-acknowledged": "Acknowledged",
        "cleared-unacknowledged": "Cleared, unacknowledged",
    },
    # alarm management on a watch: an alarm out of view (`Alarm.shelf`) or marked chattering (`Alarm.chattering`)
    "alarmMark": {"shelved": "Shelved", "chattering": "Chattering"},
    # why a shelved alarm is back in view (`Alarm.returned`), by how its shelf ended (`console.alarms.RETURNS`):
    # "back from shelving: unshelved by alice", "back from shelving at once, worse: Alpha: INS failed"
    "alarmReturned": {
        "expired": "Back from shelving: its time ended",
        "unshelved": "Back from shelving: unshelved",
        "worse": "Back from shelving at once, worse",
    },
    # ---- CoMap (IMC) ----
    "taskState": {
        "ASSIGNED": "Sent",
        "ACCEPTED": "Accepted",
        "REJECTED": "Refused",
        "IN_PROGRESS": "In progress",
        # CoMap has no acknowledgement of a SynchAdmin: what was sent, not what the vehicle did
        "HELD": "Hold sent",
        "COMPLETED": "Completed",
        "ERROR": "Error",
        "INTERRUPTED": "Interrupt sent",
    },
    "taskKind": {"survey": "Survey", "move": "Move"},
    "sensor": {
        "ANY": "Any sensor",
        "SIDESCAN": "Side-scan sonar",
        "MULTIBEAM": "Multibeam sonar",
        "CAMERA": "Camera",
        "MAGNETOMETER": "Magnetometer",
    },
    "coverage": {"NONE": "Not covered", "PARTIAL": "Partly covered", "COMPLETED": "Covered"},
}


def word(table: str, literal: str) -> str:
    """The operator's word for `literal` of `table`; a literal the table does not know (a newer ICD, another vendor's
    value) is said as it is rather than hidden."""
    return WORDS[table].get(literal, literal)


def inline(words: str) -> str:
    """A word inside a phrase: its first letter lowered, unless it starts an abbreviation ("GPS 3D", "INS")."""
    if len(words) > 1 and words[1].isupper():
        return words
    return words[:1].lower() + words[1:]
