// Where the keyboard focus goes when the button just pressed goes away with what it did (an alarm acknowledged, a
// command cancelled): left alone, the browser drops it to the page's top and a keyboard operator starts over.
import { useEffect, useRef } from "react";

/** `pressed(button, next)` in a press's handler: once that button has left the page (a later render of the component
 * calling this hook), with the focus fallen nowhere, `next()` takes it. Only that button's going moves the focus,
 * once: an operator who moved the focus meanwhile (or anything else that dropped it later) is never overruled.
 * `forget()`: the action failed and its button stays (so does the focus). The button must stay focusable while its
 * action runs (aria-disabled, not disabled, which would drop the focus at once). */
export function useFocusWhenGone(): {
  pressed: (button: HTMLElement, next: () => HTMLElement | null | undefined) => void;
  forget: () => void;
} {
  const after = useRef<{ button: HTMLElement; next: () => HTMLElement | null | undefined } | null>(null);
  useEffect(() => {
    const pending = after.current;
    if (pending === null) return;
    if (pending.button.isConnected) {
      if (document.activeElement !== pending.button) after.current = null; // the operator moved on meanwhile
      return;
    }
    after.current = null;
    const active = document.activeElement;
    if (active !== null && active !== document.body) return; // the focus went somewhere already
    pending.next()?.focus();
  });
  return {
    pressed: (button, next) => {
      after.current = { button, next };
    },
    forget: () => {
      after.current = null;
    },
  };
}
