/** Types of scripts/publish.mjs, for the registry test that runs it. */

/** A publishable workspace: its folder (`packages/cli`) and its package.json. */
export interface Publishable {
  readonly dir: string;
  readonly pkg: {
    readonly name: string;
    readonly version: string;
    readonly files?: readonly string[];
    readonly dependencies?: Readonly<Record<string, string>>;
  };
}
/** The publishable workspaces (not `private`), dependencies before their dependents. */
export function publishable(): Publishable[];
