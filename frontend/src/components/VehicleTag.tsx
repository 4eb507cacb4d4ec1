import { shortId, vehicleColor, vehicleLabel, type VehicleIdentity } from "../lib/vehicle";

/** The vehicle's colour mark, name and short id: the same wherever a vehicle is named. */
export function VehicleTag({ v }: { v: VehicleIdentity }) {
  return (
    <span className="vehicle-tag" data-testid="vehicle-tag" data-vehicle={v.id} title={v.id}>
      <span className="vehicle-mark" style={{ background: vehicleColor(v.id) }} aria-hidden="true" />
      {v.name ? (
        <>
          <span className="vehicle-tag-name">{v.name}</span> <span className="muted">{shortId(v.id)}</span>
        </>
      ) : (
        <span className="vehicle-tag-name">{vehicleLabel(v)}</span>
      )}
    </span>
  );
}
