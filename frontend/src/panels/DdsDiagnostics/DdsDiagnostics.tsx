import { useQuery } from "@tanstack/react-query";
import type { PeerFinding } from "../../api/rest";
import { useToken } from "../../data/auth";
import { useCapabilities } from "../../data/hooks";
import { peerFindingsQuery } from "../../data/queries";

/** What each kind of finding means, in the operator's words (the console's log line has the same). */
const WHAT: Record<PeerFinding["kind"], string> = {
  typeInformation: "sends type information this console cannot use: none of its SEM topics match",
  representation: "offers it in XCDR1, which the console does not read",
  unmatched: "has a writer of it that the console does not match",
  unmatchedReader: "has a reader of it that the console's commands do not reach",
};

/** The findings as a list: who, what and the exact fix (a pure view, rendered by the test too). */
export function PeerFindings({ findings }: { findings: PeerFinding[] }) {
  return (
    <section className="dds-diagnostics" data-testid="dds-diagnostics" aria-label="DDS diagnostics">
      <h2>DDS diagnostics</h2>
      <p className="muted">Participants of other vendors that the console sees in discovery but cannot read.</p>
      <ul>
        {findings.map((f) => (
          <li key={`${f.participant}/${f.kind}/${f.topic ?? ""}`} data-testid="dds-finding" data-kind={f.kind} title={f.message}>
            <strong data-testid="dds-finding-who">
              {f.vendor} participant {f.name}
            </strong>
            {f.topic ? ` · ${f.topic}` : ""}: {WHAT[f.kind]}
            <p data-testid="dds-finding-fix">Fix: {f.fix}</p>
            <p className="muted">docs/dds.md, “Connext 7.x, and the recipe for RTI vehicles”</p>
          </li>
        ))}
      </ul>
    </section>
  );
}

/** Shown only when there is something to fix, live only (a replay has no discovery). */
export function DdsDiagnostics() {
  const token = useToken();
  const live = !useCapabilities().playback;
  const findings = useQuery({ ...peerFindingsQuery(token), enabled: live }).data ?? [];
  return live && findings.length > 0 ? <PeerFindings findings={findings} /> : null;
}
