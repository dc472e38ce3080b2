"""The demo folder's index.html: the video, the plot and every summary field on one page,
linked by name inside the folder, with every text escaped."""
from html.parser import HTMLParser

from can_seeker.evaluation.demo_page import PAGE_NAME, demo_page, write_demo_page

SUMMARY = {'seed': 7, 'stopped': True, 'time_to_stop_s': 12.3456, 'final_gap_m': 0.251,
           'first_contact_s': None, 'first_contact_pose': [1.0, 2.5, 90.0],
           'contact_objects': [], 'world': 'room', 'success': True}


class PageReader(HTMLParser):
    """The page's sources by tag, its table as (header, cell) pairs and its title."""

    def __init__(self):
        super().__init__()
        self.sources = {}
        self.rows = []
        self.title = ''
        self._tag = None

    def handle_starttag(self, tag, attrs):
        attributes = dict(attrs)
        if 'src' in attributes:
            self.sources[tag] = attributes['src']
        if tag == 'tr':
            self.rows.append([])
        self._tag = tag

    def handle_data(self, data):
        if self._tag in ('th', 'td') and data.strip():
            self.rows[-1].append(data)
        elif self._tag == 'title':
            self.title += data

    def handle_endtag(self, tag):
        self._tag = None


def read(page):
    reader = PageReader()
    reader.feed(page)
    return reader


def test_the_page_shows_the_video_the_plot_and_every_summary_field():
    page = read(demo_page(SUMMARY))
    assert page.sources == {'video': 'demo.mp4', 'img': 'trajectory.png'}
    assert [row[0] for row in page.rows] == list(SUMMARY)
    cells = dict(row for row in page.rows if len(row) == 2)
    assert cells['time_to_stop_s'] == '12.346'
    assert cells['first_contact_s'] == 'n/a'
    assert cells['first_contact_pose'] == '1.000, 2.500, 90.000'
    assert cells['stopped'] == 'True'
    assert page.title == 'can_seeker demo, seed 7: SUCCESS'


def test_a_failed_run_says_so_and_text_is_escaped():
    page = demo_page(dict(SUMMARY, success=False, world='<script>alert(1)</script>'))
    assert '<script>' not in page
    assert read(page).title == 'can_seeker demo, seed 7: FAILED'
    assert ['world', '<script>alert(1)</script>'] in read(page).rows


def test_the_page_is_written_into_the_folder(tmp_path):
    path = write_demo_page(str(tmp_path), SUMMARY, video='run.mp4')
    assert path == str(tmp_path / PAGE_NAME)
    assert read((tmp_path / PAGE_NAME).read_text(encoding='utf-8')).sources['video'] == 'run.mp4'
