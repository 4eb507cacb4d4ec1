import { useSelector } from "../../data/hooks";
import { utc } from "../../lib/units";

// The console's database unreachable (an operations centre's PostgreSQL stopped or cut off): the console keeps
// monitoring and holds what it writes meanwhile. Pushed on the WebSocket (`database`) at the console's tick that finds
// it, as an alarm is: within a second of the console knowing.
export function DatabaseBanner() {
  const db = useSelector((s) => s.database);
  const since = db?.unavailableSince;
  if (db == null || since == null) return null;
  return (
    <p className="alarm" role="alert" data-testid="database-banner">
      Shared history unavailable since {utc(since)}: this console keeps monitoring and holds its commands, transitions, audit and
      acknowledgements ({db.writesHeld} held) until the database is back.
      {db.writesDropped
        ? ` ${db.writesDropped} of the oldest were dropped (more than 50,000 held): ` +
          "they are missing from the shared history."
        : ""}
    </p>
  );
}
