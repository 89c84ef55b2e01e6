"""`ifslib.automatic.fractal.board`: the search decides on full-precision `Row` records, and rounds only what it
writes."""
from __future__ import annotations

import math
from dataclasses import FrozenInstanceError, replace

import pytest

from ifslib.automatic.fractal import DEFAULT
from ifslib.automatic.fractal.board import Board, Context, Row


def _board(*rows: Row, turned=(), config=DEFAULT) -> Board:
    context = Context(None, None, None, None, {}, None, None, 0, config)  # the decisions read the config alone
    return Board(context, rows={r.maps: r for r in rows}, turned=list(turned))


def _row(k: int, iou: float, chamfer: float = 1.0, config=DEFAULT) -> Row:
    return Row(maps=k, cover=0.9, collage_px=0.5, chamfer_px=chamfer, iou=iou, score=1 - iou + config.map_cost * k)


def test_a_row_is_frozen_and_written_rounded_with_the_moves_that_apply():
    row = Row(maps=3, cover=0.123456, collage_px=1.234567, chamfer_px=0.987654, iou=0.876543, score=0.243457,
              seconds=1.23456, regions=2)
    with pytest.raises(FrozenInstanceError):
        row.iou = 1.0
    assert row.written() == {"maps": 3, "cover": 0.1235, "collage_px": 1.2346, "chamfer_px": 0.9877, "iou": 0.8765,
                             "score": 0.2435, "seconds": 1.23, "regions": 2}
    assert list(replace(row, swapped=1, reoriented=True).written())[-3:] == ["reoriented", "regions", "swapped"]
    assert math.isnan(Row(maps=2, cover=1.0, collage_px=0.0).iou)  # not judged yet


def test_the_best_row_is_chosen_on_full_precision_scores_not_on_the_rounded_ones():
    # two rows whose scores are equal to 4 digits: the fewer maps won on the rounded scores, the lesser score wins now
    three = _row(3, iou=0.80000)
    four = replace(_row(4, iou=0.84004), score=three.score - 4e-5)
    board = _board(three, four, turned=(3, 4))
    assert round(three.score, 4) == round(four.score, 4)
    assert board.best() is four and board.by_score(board.turned_rows) == [four, three]
    assert board.best([three]) is three


def test_fits_and_stuck_read_the_iou_at_full_precision():
    bar = DEFAULT.swap_below
    below = _board(_row(3, iou=bar - 1e-6), turned=(3,))
    assert round(bar - 1e-6, 4) == bar  # the file's row would say it fits
    assert not below.fits() and below.stuck()
    at = _board(_row(3, iou=bar), turned=(3,))
    assert at.fits() and not at.stuck()
    assert not _board(_row(3, iou=0.1)).stuck()  # nothing reoriented yet: no moves


def test_declines_by_the_chamfer_score_and_gives_up_far_from_the_target():
    cost = DEFAULT.chamfer_cost
    board = _board(_row(2, iou=0.9, chamfer=0.15))  # scores 0.15 + 2 cost: 5 maps score at least 5 cost, no less
    assert board.declines(5) and board.skipped == [5]
    assert not board.declines(3) and board.skipped == [5]
    far = _board(_row(2, iou=0.1, chamfer=DEFAULT.give_up_px + 1e-9), _row(3, iou=0.1, chamfer=50.0))
    k = DEFAULT.give_up_maps + 1
    assert far.chamfer_score(far.rows[2]) == pytest.approx(DEFAULT.give_up_px + 2 * cost)
    assert far.declines(k) and far.hopeless == [k]
    near = _board(_row(2, iou=0.1, chamfer=DEFAULT.give_up_px))
    assert not near.declines(k)


def test_change_and_add_time_replace_the_row():
    board = _board(_row(2, iou=0.5))
    before = board.rows[2]
    after = board.change(2, regions=1)
    assert after.regions == 1 and before.regions == 0 and board.rows[2] is after
    assert board.add_time(2, 0.0).seconds > 0
