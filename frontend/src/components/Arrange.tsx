// Rearranging the panels of a group (dnd-kit): drag a panel by its ⠿ handle, or focus the handle and
// press Space, the arrow keys, Space; or use its ↑ ↓ buttons. The order is kept in the settings store.
import { createContext, useContext, useRef, useState, type CSSProperties, type ReactNode } from "react";
import {
  DndContext,
  KeyboardSensor,
  PointerSensor,
  closestCenter,
  useSensor,
  useSensors,
  type Announcements,
  type DragEndEvent,
  type UniqueIdentifier,
} from "@dnd-kit/core";
import {
  SortableContext,
  rectSortingStrategy,
  sortableKeyboardCoordinates,
  useSortable,
  verticalListSortingStrategy,
} from "@dnd-kit/sortable";
import { CSS } from "@dnd-kit/utilities";
import { usePanelOrder } from "../data/settings";
import { moveBy, moveTo, type Group } from "../lib/layout";

interface Slot {
  handle: Pick<ReturnType<typeof useSortable>, "attributes" | "listeners" | "setActivatorNodeRef">;
  move: (by: number) => void;
  first: boolean;
  last: boolean;
}

const SlotContext = createContext<Slot | null>(null);

interface GroupProps {
  group: Group;
  panels: Record<string, { node: ReactNode; wide?: boolean }>;
  className: string;
  testId: string;
  label: string;
}

/** The panels of one group, in the operator's order (by default that of `panels`), each movable within the group. */
export function ArrangeableGroup({ group, panels, className, testId, label }: GroupProps) {
  const [order, setOrder] = usePanelOrder(group, Object.keys(panels));
  const [said, setSaid] = useState(""); // what a screen reader hears after a move by the ↑ ↓ buttons
  const sensors = useSensors(
    useSensor(PointerSensor, { activationConstraint: { distance: 5 } }),
    useSensor(KeyboardSensor, { coordinateGetter: sortableKeyboardCoordinates }),
  );
  // what a screen reader says while a panel is moved: its title and the place it would take
  const name = (id: UniqueIdentifier) =>
    document.querySelector(`[data-panel="${String(id)}"] > section`)?.getAttribute("aria-label") ?? String(id);
  const place = (id: UniqueIdentifier) => `place ${order.indexOf(String(id)) + 1} of ${order.length}`;
  const announcements: Announcements = {
    onDragStart: ({ active }) => `Picked up ${name(active.id)}, at ${place(active.id)}.`,
    onDragOver: ({ active, over }) =>
      over ? `${name(active.id)} over ${place(over.id)}.` : `${name(active.id)} is over no place.`,
    onDragEnd: ({ active, over }) =>
      over ? `${name(active.id)} dropped at ${place(over.id)}.` : `${name(active.id)} dropped where it was.`,
    onDragCancel: ({ active }) => `Moving ${name(active.id)} cancelled.`,
  };
  const onDragEnd = ({ active, over }: DragEndEvent) => {
    if (over && active.id !== over.id) setOrder(moveTo(order, String(active.id), order.indexOf(String(over.id))));
  };
  return (
    <DndContext sensors={sensors} collisionDetection={closestCenter} onDragEnd={onDragEnd} accessibility={{ announcements }}>
      <SortableContext items={order} strategy={group === "main" ? rectSortingStrategy : verticalListSortingStrategy}>
        <div className={className} data-testid={testId} aria-label={label} role="group">
          {order.map((id, i) => (
            <SortableSlot
              key={id}
              id={id}
              wide={panels[id].wide}
              first={i === 0}
              last={i === order.length - 1}
              move={(by) => {
                const next = moveBy(order, id, by);
                setOrder(next);
                setSaid(`${name(id)} moved to place ${next.indexOf(id) + 1} of ${next.length}.`);
              }}
            >
              {panels[id].node}
            </SortableSlot>
          ))}
        </div>
      </SortableContext>
      <div role="status" className="visually-hidden" data-testid={`${testId}-status`}>
        {said}
      </div>
    </DndContext>
  );
}

function SortableSlot({
  id,
  wide,
  first,
  last,
  move,
  children,
}: {
  id: string;
  wide?: boolean;
  first: boolean;
  last: boolean;
  move: (by: number) => void;
  children: ReactNode;
}) {
  const { attributes, listeners, setNodeRef, setActivatorNodeRef, transform, transition, isDragging } = useSortable({ id });
  const style: CSSProperties = {
    transform: CSS.Translate.toString(transform),
    transition,
    zIndex: isDragging ? 3 : undefined,
    opacity: isDragging ? 0.85 : undefined,
  };
  return (
    <div ref={setNodeRef} style={style} className={`slot${wide ? " wide" : ""}${isDragging ? " dragging" : ""}`} data-panel={id}>
      <SlotContext.Provider value={{ handle: { attributes, listeners, setActivatorNodeRef }, move, first, last }}>
        {children}
      </SlotContext.Provider>
    </div>
  );
}

/** The drag handle of the panel's slot (nothing for a panel outside an arrangeable group). */
export function DragHandle({ title, testId }: { title: string; testId: string }) {
  const slot = useContext(SlotContext);
  if (!slot) return null;
  const { attributes, listeners, setActivatorNodeRef } = slot.handle;
  return (
    <button
      ref={setActivatorNodeRef}
      className="drag-handle"
      {...attributes}
      {...listeners}
      aria-label={`Move ${title}: drag, or press Space then the arrow keys and Space`}
      title="drag to move the panel (or Space, arrow keys, Space)"
      data-testid={`${testId}-drag`}
    >
      ⠿
    </button>
  );
}

/** The ↑ ↓ buttons that move the panel one place earlier or later in its group. */
export function MoveButtons({ title, testId }: { title: string; testId: string }) {
  const slot = useContext(SlotContext);
  const earlier = useRef<HTMLButtonElement>(null);
  const later = useRef<HTMLButtonElement>(null);
  if (!slot) return null;
  // the panel's node moves in the page, which can take the focus away: give it back to the button
  const press = (by: number) => {
    slot.move(by);
    requestAnimationFrame(() => {
      const [b, other] = by < 0 ? [earlier.current, later.current] : [later.current, earlier.current];
      (b && !b.disabled ? b : other)?.focus();
    });
  };
  return (
    <span className="move-buttons">
      <button
        ref={earlier}
        className="move"
        disabled={slot.first}
        aria-label={`Move ${title} earlier`}
        title="move earlier (up or left)"
        onClick={() => press(-1)}
        data-testid={`${testId}-earlier`}
      >
        ↑
      </button>
      <button
        ref={later}
        className="move"
        disabled={slot.last}
        aria-label={`Move ${title} later`}
        title="move later (down or right)"
        onClick={() => press(1)}
        data-testid={`${testId}-later`}
      >
        ↓
      </button>
    </span>
  );
}
