import { useQuery } from "@tanstack/react-query";
import { healthQuery } from "../data/queries";
import { utc } from "../lib/units";

// The console's database unreachable (an operations centre's PostgreSQL stopped or cut off): the console keeps
// monitoring and holds what it writes meanwhile (GET /api/health says since when). Asked every 5 s while shown
// and every 15 s otherwise: an outage is a server matter, not a live stream.
export function DatabaseBanner() {
  const { data } = useQuery({ ...healthQuery(), queryKey: ["health", "database"], staleTime: 0,
    refetchInterval: (q) => (q.state.data?.databaseUnavailableSince != null ? 5_000 : 15_000) });
  const since = data?.databaseUnavailableSince;
  if (since == null) return null;
  return (
    <p className="alarm" role="alert" data-testid="database-banner">
      Shared history unavailable since {utc(since)}: this console keeps monitoring and holds its commands, transitions,
      audit and acknowledgements ({data?.databaseWritesHeld ?? 0} held) until the database is back.
      {data?.databaseWritesDropped ? ` ${data.databaseWritesDropped} of the oldest were dropped (more than 50,000 held): ` +
        "they are missing from the shared history." : ""}
    </p>
  );
}
