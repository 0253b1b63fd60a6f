import { comingChapter } from '../ui/coming.js';

// Being built (issue 4); replaced by the chapter's demo.
export const mount = comingChapter({ number: 8, title: 'Final fixes', lede: '', coming: [] });
