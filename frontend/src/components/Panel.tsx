import type { ReactNode } from "react";
import { ErrorBoundary } from "./ErrorBoundary";
import type { Freshness } from "../lib/freshness";
import { age } from "../lib/units";

interface Props {
  title: string;
  testId: string;
  freshness?: Freshness;
  ageSeconds?: number | null;
  actions?: ReactNode;
  children: ReactNode;
  className?: string;
}

export function Panel({ title, testId, freshness, ageSeconds, actions, children, className }: Props) {
  return (
    <section className={`panel ${className ?? ""}`} data-testid={testId} aria-label={title}>
      <header className="panel-head">
        <h2>{title}</h2>
        {freshness && freshness !== "none" && (
          <span className={`fresh fresh-${freshness}`} data-testid={`${testId}-freshness`} title="age of the latest data">
            {freshness === "live" ? "live" : freshness} · {age(ageSeconds ?? null)}
          </span>
        )}
        {actions}
      </header>
      <ErrorBoundary name={title}>{children}</ErrorBoundary>
    </section>
  );
}

interface FieldProps {
  label: string;
  value: string;
  stale?: boolean;
  invalid?: string | null;
  testId?: string;
}

/** A labelled value; stale values are dimmed and marked, invalid ones flagged with the reason. */
export function Field({ label, value, stale, invalid, testId }: FieldProps) {
  return (
    <div className={`field${stale ? " stale" : ""}${invalid ? " invalid" : ""}`} title={invalid ?? (stale ? "stale: no fresh data" : undefined)}>
      <span className="label">{label}</span>
      <span className="value" data-testid={testId}>
        {value}
        {invalid ? " ⚠" : ""}
      </span>
    </div>
  );
}

/** The invalid-reason for a member path (as the backend lists them), if any. */
export function invalidFor(invalid: string[] | undefined, path: string): string | null {
  return invalid?.find((x) => x.startsWith(`${path}:`) || x.startsWith(`${path}.`)) ?? null;
}
