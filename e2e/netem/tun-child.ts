/**
 * Runs inside the network namespace tun.ts made: the model comparison over the kernel's TCP through
 * the TUN link. Argument: JSON `{ models, seconds, link, seed }`; prints one `row <json>` line per
 * model (a `ModelRow`).
 */
import type { Impairment } from './impair.js';
import { tunLink } from './links.js';
import { runModelMatch, type Model } from './model-match.js';

const args = JSON.parse(process.argv[2] ?? '{}') as {
  models: Model[];
  seconds: number;
  link: Impairment;
  seed: number;
};
for (const model of args.models) {
  const row = await runModelMatch({
    model,
    seconds: args.seconds,
    seed: args.seed,
    connect: (accept) => tunLink(args.link, args.seed, accept),
  });
  console.log(`row ${JSON.stringify(row)}`);
}
// Done: whatever a closed socket's timer still holds, the rows are out.
process.exit(0);
