import { comingChapter } from '../ui/coming.js';

// Being built (issue 4); replaced by the chapter's demo.
export const mount = comingChapter({ number: 2, title: 'Movement', lede: '', coming: [] });
