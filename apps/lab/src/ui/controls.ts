/**
 * Controls every chapter uses: buttons, toggles, a segmented choice, a labelled group, the time
 * controls (Pause / Skip / Restart) with the virtual clock's readout. Styled by styles.css.
 */
import { h, setAttr, setText } from './dom.js';
import * as fmt from './format.js';

/** A button with a test id. */
export function button(label: string, testId: string, onClick: () => void): HTMLButtonElement {
  const b = h('button', { type: 'button', class: 'btn', 'data-testid': testId }, label);
  b.addEventListener('click', onClick);
  return b;
}

/** A toggle button (`aria-pressed`), calling `onChange` with its new state. */
export function toggle(
  label: string,
  testId: string,
  initial: boolean,
  onChange: (on: boolean) => void,
): HTMLButtonElement {
  const b = h(
    'button',
    { type: 'button', class: 'btn toggle', 'data-testid': testId, 'aria-pressed': String(initial) },
    label,
  );
  b.addEventListener('click', () => {
    const on = b.getAttribute('aria-pressed') !== 'true';
    b.setAttribute('aria-pressed', String(on));
    onChange(on);
  });
  return b;
}

/** Sets a toggle's state without calling its handler. */
export function setPressed(b: HTMLButtonElement, on: boolean): void {
  setAttr(b, 'aria-pressed', String(on));
}

/** A labelled row of controls inside a `.controls` box. */
export function group(label: string, ...children: (Node | null)[]): HTMLElement {
  return h(
    'div',
    { class: 'control-group' },
    h('span', { class: 'control-label' }, label),
    ...children,
  );
}

export interface Segmented<T extends string | number> {
  readonly el: HTMLElement;
  readonly inputs: Map<T, HTMLInputElement>;
  /** Select `value` without calling the handler. */
  select(value: T): void;
  setDisabled(disabled: boolean): void;
}

/**
 * A radio group drawn as a segmented control. `name` must be unique on the page; each option
 * gets the test id `${testPrefix}-${value}`.
 */
export function segmented<T extends string | number>(options: {
  name: string;
  label: string;
  testPrefix: string;
  values: readonly T[];
  selected: T;
  text: (value: T) => string;
  onChange: (value: T) => void;
}): Segmented<T> {
  const inputs = new Map<T, HTMLInputElement>();
  const el = h(
    'div',
    { class: 'segmented', role: 'radiogroup', 'aria-label': options.label },
    options.values.map((value) => {
      const id = `${options.name}-${value}`;
      const input = h('input', {
        type: 'radio',
        name: options.name,
        value: String(value),
        id,
        checked: value === options.selected,
      });
      input.addEventListener('change', () => {
        if (input.checked) options.onChange(value);
      });
      inputs.set(value, input);
      return h(
        'label',
        { for: id, 'data-testid': `${options.testPrefix}-${value}` },
        input,
        h('span', {}, options.text(value)),
      );
    }),
  );
  return {
    el,
    inputs,
    select(value) {
      const input = inputs.get(value);
      if (input) input.checked = true;
    },
    setDisabled(disabled) {
      for (const input of inputs.values()) input.disabled = disabled;
    },
  };
}

export interface Slider {
  readonly input: HTMLInputElement;
  readonly output: HTMLOutputElement;
  readonly el: HTMLElement;
  set(value: number): void;
}

/**
 * A labelled range input with its value shown beside it. `onChange` fires when the slider is let
 * go (a replay per pixel dragged would be wasteful); the label follows while dragging.
 */
export function slider(options: {
  id: string;
  label: string;
  testId: string;
  min: number;
  max: number;
  step: number;
  value: number;
  text: (value: number) => string;
  onChange: (value: number) => void;
}): Slider {
  const input = h('input', {
    type: 'range',
    min: options.min,
    max: options.max,
    step: options.step,
    value: options.value,
    id: options.id,
    'data-testid': options.testId,
    'aria-describedby': `${options.id}-out`,
  });
  const output = h(
    'output',
    { id: `${options.id}-out`, for: options.id },
    options.text(options.value),
  );
  input.addEventListener('input', () => {
    setText(output, options.text(Number(input.value)));
  });
  input.addEventListener('change', () => {
    options.onChange(Number(input.value));
  });
  const el = h(
    'div',
    { class: 'control-group' },
    h('label', { class: 'control-label', for: options.id }, options.label),
    input,
    output,
  );
  return {
    input,
    output,
    el,
    set(value) {
      input.value = String(value);
      setText(output, options.text(value));
    },
  };
}

/**
 * A simulated display's frame jitter (test id `control-jitter`): 0 to 30 % of its period in steps
 * of 1 %, shown as `±5 %` unless `text` says otherwise; `onChange` gets it as a fraction.
 */
export function jitterSlider(options: {
  id: string;
  /** The jitter at the start, per cent. */
  percent: number;
  text?: (percent: number) => string;
  onChange: (fraction: number) => void;
}): Slider {
  return slider({
    id: options.id,
    label: 'Jitter',
    testId: 'control-jitter',
    min: 0,
    max: 30,
    step: 1,
    value: options.percent,
    text: options.text ?? ((v) => `±${v} %`),
    onChange: (v) => {
      options.onChange(v / 100);
    },
  });
}

/** A simulated link's conditions, as its sliders show them. */
export interface LinkValues {
  latencyMs: number;
  jitterMs: number;
  /** 0–1. */
  loss: number;
}

/** The three sliders of a simulated link, and how to show new values on them. */
export interface LinkSliders {
  latency: Slider;
  jitter: Slider;
  loss: Slider;
  /** Show `link` (after a change made elsewhere). */
  set(link: LinkValues): void;
}

/**
 * A simulated link's latency (0–250 ms), jitter (± 0–100 ms) and loss (0–20 %) sliders (ids
 * `${idPrefix}-latency` …, test ids `control-latency`, `control-jitter`, `control-loss`), set to
 * `link`; `onChange` gets the one value changed (loss as a fraction).
 */
export function linkSliders(options: {
  idPrefix: string;
  link: Readonly<LinkValues>;
  onChange: (change: Partial<LinkValues>) => void;
}): LinkSliders {
  const { idPrefix, link, onChange } = options;
  const delay = (
    key: 'latencyMs' | 'jitterMs',
    id: string,
    label: string,
    max: number,
    text: (v: number) => string,
  ) =>
    slider({
      id: `${idPrefix}-${id}`,
      label,
      testId: `control-${id}`,
      min: 0,
      max,
      step: 5,
      value: link[key],
      text,
      onChange: (v) => {
        onChange({ [key]: v });
      },
    });
  const latency = delay('latencyMs', 'latency', 'Latency', 250, (v) => `${v} ms`);
  const jitter = delay('jitterMs', 'jitter', 'Jitter', 100, (v) => `± ${v} ms`);
  const loss = slider({
    id: `${idPrefix}-loss`,
    label: 'Loss',
    testId: 'control-loss',
    min: 0,
    max: 20,
    step: 1,
    value: Math.round(link.loss * 100),
    text: (v) => `${v} %`,
    onChange: (v) => {
      onChange({ loss: v / 100 });
    },
  });
  return {
    latency,
    jitter,
    loss,
    set(l) {
      latency.set(l.latencyMs);
      jitter.set(l.jitterMs);
      loss.set(Math.round(l.loss * 100));
    },
  };
}

/** Pause / Skip / Restart and the clock readout (`readout-clock`, virtual ms in `data-value`). */
export class TimeControls {
  readonly pauseBtn: HTMLButtonElement;
  readonly skipBtn: HTMLButtonElement;
  readonly restartBtn: HTMLButtonElement;
  readonly clockOut: HTMLElement;
  readonly modeOut: HTMLElement;
  /** The buttons, for a control group. */
  readonly buttons: HTMLButtonElement[];
  /** `t = …` and the mode line, for the status row. */
  readonly status: HTMLElement[];

  constructor(handlers: {
    onPause: () => void;
    onSkip: () => void;
    onRestart: () => void;
    skipMs: number;
  }) {
    this.pauseBtn = button('Pause', 'control-pause', handlers.onPause);
    this.pauseBtn.setAttribute('aria-pressed', 'false');
    this.skipBtn = button(`Skip +${handlers.skipMs / 1000} s`, 'control-skip', handlers.onSkip);
    this.skipBtn.title = `Advance the simulated display by ${handlers.skipMs / 1000} s at once`;
    this.restartBtn = button('Restart', 'control-restart', handlers.onRestart);
    this.clockOut = h('span', { class: 'clock', 'data-testid': 'readout-clock' }, '0.000 s');
    this.modeOut = h('span', { class: 'mode' });
    this.buttons = [this.pauseBtn, this.skipBtn, this.restartBtn];
    this.status = [h('span', { class: 'status-item' }, 't = ', this.clockOut), this.modeOut];
  }

  /** Show the pause state and whether Skip applies (only on the simulated display). */
  refresh(paused: boolean, simulated: boolean): void {
    setText(this.pauseBtn, paused ? 'Play' : 'Pause');
    setAttr(this.pauseBtn, 'aria-pressed', String(paused));
    this.skipBtn.disabled = !simulated;
  }

  /** Show the clock (virtual ms) and a mode line. */
  show(timeMs: number, mode: string): void {
    setText(this.clockOut, fmt.seconds(timeMs / 1000));
    setAttr(this.clockOut, 'data-value', fmt.exact(timeMs));
    setText(this.modeOut, mode);
  }
}

/**
 * A slider that walks a ladder of values (stiffness 5, 10, 20, 50 … N/m): the range input holds
 * the rung, the output and `aria-valuetext` the value with its unit. `onChange` fires when let go.
 */
export function ladderSlider(options: {
  id: string;
  label: string;
  testId: string;
  values: readonly number[];
  value: number;
  unit: string;
  onChange: (value: number) => void;
}): Slider {
  const { values, unit } = options;
  const valueAt = (rung: number) =>
    values[Math.min(values.length - 1, Math.max(0, Math.round(rung)))] ?? values[0]!;
  const s = slider({
    id: options.id,
    label: options.label,
    testId: options.testId,
    min: 0,
    max: values.length - 1,
    step: 1,
    value: Math.max(0, values.indexOf(options.value)),
    text: (rung) => `${valueAt(rung)} ${unit}`,
    onChange: (rung) => {
      options.onChange(valueAt(rung));
    },
  });
  const show = (value: number) => {
    setAttr(s.input, 'aria-valuetext', `${value} ${unit}`);
  };
  show(options.value);
  s.input.addEventListener('input', () => {
    show(valueAt(Number(s.input.value)));
  });
  return {
    ...s,
    set(value) {
      const i = values.indexOf(value);
      if (i >= 0) s.set(i);
      show(value);
    },
  };
}
