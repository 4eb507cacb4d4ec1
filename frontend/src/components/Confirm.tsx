// The one confirmation of the dashboard (commands, CoMap tasks): shown in place, next to what it confirms.
// It takes the keyboard focus when shown, so a keyboard or screen-reader user is on it at once, and Esc
// (anywhere on the page) closes it without sending: cancelling is always the safe answer.
import { useEffect, useRef, type ReactNode } from "react";

interface Props {
  label: string; // the dialog's accessible name, e.g. "Confirm command"
  confirmText: string; // the button that sends, e.g. "Confirm" or "Send anyway"
  cancelText?: string;
  onConfirm: () => void;
  onCancel: () => void;
  children: ReactNode; // what is confirmed, naming the vehicle
  vehicle?: string; // the vehicle it is bound to (data-vehicle, for the tests and the page's own checks)
  testId?: string;
}

export function Confirm({
  label,
  confirmText,
  cancelText = "Keep as is",
  onConfirm,
  onCancel,
  children,
  vehicle,
  testId,
}: Props) {
  const box = useRef<HTMLDivElement>(null);
  const cancel = useRef(onCancel);
  useEffect(() => {
    cancel.current = onCancel;
  });

  useEffect(() => {
    // the dialog itself takes focus, not its Confirm button: a second Enter meant for the button that
    // opened it must not send the command
    const before = document.activeElement instanceof HTMLElement ? document.activeElement : null;
    box.current?.focus();
    const onKey = (e: KeyboardEvent) => {
      if (e.key !== "Escape") return;
      e.preventDefault();
      cancel.current();
    };
    document.addEventListener("keydown", onKey);
    const node = box.current;
    return () => {
      document.removeEventListener("keydown", onKey);
      // back to where the operator was, unless they have moved on (e.g. clicked another vehicle)
      const active = document.activeElement;
      if (
        before &&
        before.isConnected &&
        (active === null || active === document.body || (node !== null && node.contains(active)))
      )
        before.focus();
    };
  }, []);

  return (
    // not aria-modal: the page stays usable beside it (another vehicle selected voids it), and a modal
    // dialog would hide the rest of the page from a screen reader
    <div ref={box} className="confirm" role="dialog" aria-label={label} tabIndex={-1} data-vehicle={vehicle} data-testid={testId}>
      {children}
      <button className="danger" onClick={onConfirm}>
        {confirmText}
      </button>
      <button onClick={onCancel}>{cancelText}</button>
    </div>
  );
}
