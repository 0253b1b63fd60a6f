/**
 * The model behind a chapter that runs on the lab's virtual clock: its settings, and a virtual
 * time it is moved forward to (by the page's frames, "Skip", or a replay of the settings from
 * zero). A subclass builds its runs from {@link VirtualLab.current} and moves them in
 * {@link VirtualLab.advanceTo}.
 */
export abstract class VirtualLab<S> {
  /** Virtual time, ms. */
  protected time = 0;

  constructor(
    /** The settings in force (the subclass replaces them on a change). */
    protected current: S,
  ) {}

  get settings(): Readonly<S> {
    return this.current;
  }

  /** Virtual time, ms. */
  get timeMs(): number {
    return this.time;
  }

  /** Move every run forward to virtual time `tMs`. */
  abstract advanceTo(tMs: number): void;

  advanceBy(ms: number): void {
    this.advanceTo(this.time + ms);
  }
}
