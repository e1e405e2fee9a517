"""Runs through the binding: items, buffers each way, stats as dicts."""
import os
import subprocess
import sys

import numpy as np
import pytest

import perma
from conftest import MIX, NODE


def tree_weight(depth, weights):
    """What split adds to weight_sum for a tree of this depth: 2^(depth-k) nodes of depth k."""
    return sum((1 << (depth - k)) * int(weights[k]) for k in range(depth + 1))


def test_tree_counts_and_stats(workloads):
    w = workloads
    stats = w.tree(12)
    assert w.leaves[0] == 4096
    assert w.weight_sum[0] == tree_weight(12, w.weights)
    assert np.array_equal(w.leaf_ids, np.arange(1, 4097, dtype=np.uint32))
    assert stats['items'] == 8191
    assert stats['technique'] == 'megakernel' and stats['strategy'] == 'shared'
    assert stats['launches'] >= 1 and stats['seconds'] > 0
    split = stats['procedures']['split']
    assert split['name'] == 'split'
    assert split['items'] == 8191 and split['seeded'] == 1
    assert split['emitted'] == {'split': 8190}
    assert stats['procedures']['greedy']['items'] == 0
    assert stats['procedures']['greedy']['emitted'] == {'split': 0}
    groups, group_size = w.rt.work_groups
    assert len(stats['groups']) == groups == stats['work_groups'] and group_size == stats['group_size']
    assert sum(g['items'] for g in stats['groups']) == 8191
    assert w.rt.procedure_stats('split') == split
    assert w.rt.group_stats(0) == stats['groups'][0]


def test_queue_only_items_go_through_the_queues(workloads):
    """split runs from the work-items' stacks (work-first); countdown is queue_only."""
    w = workloads
    stats = w.tree(10)
    assert stats['stack_items'] > 0
    assert stats['procedures']['split']['stacked_items'] > 1000
    w.rt.seed(w.countdown, np.array([(500, 0)], NODE))
    stats = w.rt.run()
    assert stats['procedures']['countdown']['items'] == 501
    assert stats['procedures']['countdown']['stacked_items'] == 0
    assert stats['stacked_items'] == 0


def test_reductions(workloads):
    w = workloads
    stats = w.tree(12)
    nodes = w.rt.reduction('nodes')
    assert nodes == 8191 and nodes.dtype == np.uint64
    deepest = w.rt.reduction('deepest')
    assert deepest == 12 and deepest.dtype == np.uint32
    assert w.rt.reduction('last_id') == -4095 and w.rt.reduction('last_id').dtype == np.int32
    assert w.rt.reduction('weight') == tree_weight(12, w.weights) / 2
    assert stats['reductions'] == {'nodes': 8191, 'deepest': 12, 'last_id': -4095,
                                   'weight': tree_weight(12, w.weights) / 2}
    assert [type(v) for v in stats['reductions'].values()] == [np.uint64, np.uint32, np.int32, np.float64]
    w.tree(3, 0)  # each run starts from the identities
    assert w.rt.stats()['reductions'] == {'nodes': 15 + 1, 'deepest': 3, 'last_id': -7,
                                          'weight': (tree_weight(3, w.weights) + tree_weight(0, w.weights)) / 2}


def test_several_roots_in_one_run(workloads):
    w = workloads
    stats = w.tree(3, 5, 0)
    assert w.leaves[0] == 8 + 32 + 1
    assert w.weight_sum[0] == tree_weight(3, w.weights) + tree_weight(5, w.weights) + tree_weight(0, w.weights)
    assert stats['procedures']['split']['seeded'] == 3
    assert stats['items'] == 15 + 63 + 1


def test_write_only_buffer_is_not_copied_in(workloads):
    """access='write': copied back after the run, never to the device, so
    what the run does not write keeps the device's earlier contents."""
    w = workloads
    w.tree(12)
    w.leaf_ids[:] = 0xFFFFFFFF
    w.tree(3)
    assert np.array_equal(w.leaf_ids[:8], np.arange(1, 9))
    assert np.array_equal(w.leaf_ids[8:], np.arange(9, 4097))


def test_read_buffer_is_copied_in_before_each_run(workloads):
    w = workloads
    saved = w.weights.copy()
    try:
        w.weights[:] = 7
        w.tree(4)
        assert w.weight_sum[0] == 7 * 31
    finally:
        w.weights[:] = saved
    w.tree(4)
    assert w.weight_sum[0] == tree_weight(4, saved)


def test_binding_again_swaps_the_array(workloads):
    w = workloads
    other = np.zeros(1, np.uint32)
    w.rt.bind('leaves', other)
    try:
        w.tree(5)
        assert other[0] == 32
        assert w.leaves[0] == 0  # tree() zeroed it; the run wrote `other`
    finally:
        w.rt.bind('leaves', w.leaves)
    w.tree(2)
    assert w.leaves[0] == 4 and other[0] == 32


def test_seeds_from_a_list_of_tuples(workloads):
    w = workloads
    w.leaves[:] = 0
    w.rt.seed('split', [(6, 0)])
    w.rt.run()
    assert w.leaves[0] == 64


def test_struct_items_keep_their_layout_on_the_device(workloads):
    """Items of a dtype with every field size, a nested array and padding
    come back byte for byte from a procedure that copies them."""
    w = workloads
    items = np.zeros(16, MIX)
    items['index'] = np.arange(16)[::-1]
    items['flag'] = np.arange(16) * 3
    items['value'] = np.linspace(-1e300, 1e300, 16)
    items['pair']['x'] = np.arange(32).reshape(16, 2) - 16
    items['pair']['y'] = np.arange(96).reshape(16, 2, 3)
    items['big'] = -(np.arange(16, dtype=np.int64) << 40)
    items['f'] = np.arange(48, dtype=np.float32).reshape(16, 3) / 7
    w.copies[:] = np.zeros(16, MIX)
    w.rt.seed(w.copy, items)
    w.rt.run()
    assert MIX.itemsize == 56
    assert w.copies.tobytes() == np.sort(items, order='index').tobytes()


def test_find(workloads):
    assert workloads.rt.find('split') is workloads.split
    with pytest.raises(perma.ArgumentError, match="no procedure named 'nope'") as info:
        workloads.rt.find('nope')
    assert info.value.status == perma.Status.ARGUMENT


def test_stats_text(workloads):
    workloads.tree(4)
    text = workloads.rt.stats_text()
    assert text.startswith('perma run (megakernel, shared)')
    assert 'split' in text and 'split:30' in text


def test_device_and_schedule_options(make_workloads):
    """A schedule label and a device list entry reach perma_create."""
    w = make_workloads(schedule='kernel-per-procedure', device='0:0')
    stats = w.tree(10)
    assert w.leaves[0] == 1024
    assert stats['technique'] == 'kernel-per-procedure'
    assert stats['items'] == 2047


def test_work_groups_and_group_size_options():
    with perma.Runtime(work_groups=1, group_size=32) as rt:
        assert rt.work_groups == (1, 32)
        assert ': 1 work-groups' in rt.device_summary


def test_devices():
    every = perma.devices('all')
    assert every and all(isinstance(d, perma.Device) for d in every)
    assert perma.devices('0:0') == [perma.Device(0, 0, 0, 0)]
    halves = perma.devices('0:0/2')
    assert [str(d) for d in halves] == ['0:0/2.0', '0:0/2.1']


def test_schedule_labels():
    assert perma.schedule_label('megakernel') == 'megakernel/shared'
    assert perma.schedule_label('megakernel/stealing+local32') == 'megakernel/stealing/random+local32'
    assert perma.schedule_label('bounded-batches/p=64') == 'bounded-batches/p=64'
    assert perma.schedule_label('megakernel/stealing-donation/d=64+local32') == \
        'megakernel/stealing-donation/random/d=64+local32'


def test_donation_threshold_is_part_of_the_schedule():
    """The label's /d=N fills perma_schedule.donation_threshold (the
    struct's last field: the ABI check covers its offset)."""
    schedule = perma.schedule.parse_schedule('megakernel/donation/d=256')
    assert schedule.donation_threshold == 256
    assert perma.schedule.format_schedule(schedule) == 'megakernel/donation/d=256'
    assert perma.schedule.parse_schedule('megakernel/donation').donation_threshold == 0


@pytest.mark.parametrize('which', ['all', 'once', 'default'])
def test_every_schedule_matches_the_configure_time_list(which):
    """meson's test variants (runtime/tools/schedules.py, which reads the
    schedule table before libperma exists) are perma_schedule_all's."""
    labels = perma.all_schedules(which)
    assert labels[0] == 'megakernel/shared' and 'kernel-per-procedure' in labels
    assert all(perma.schedule_label(label) == label for label in labels)
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'runtime', 'tools', 'schedules.py')
    printed = subprocess.run([sys.executable, script, which], check=True, capture_output=True, text=True).stdout
    variants = subprocess.run([sys.executable, script, '--variants', which], check=True, capture_output=True,
                              text=True).stdout
    assert printed.split() == labels
    # A variant's name is its label with '-' for '/', without the default victim.
    names = [line.split('|')[0] for line in variants.split()]
    assert names == [label.replace('/random', '').replace('/', '-') for label in labels]


def test_all_schedules_refuses_an_unknown_set():
    with pytest.raises(perma.ArgumentError, match='which schedules'):
        perma.all_schedules('some')


def test_context_manager_closes():
    with perma.Runtime() as rt:
        assert rt.work_groups[0] >= 1
    with pytest.raises(perma.StateError, match='closed') as info:
        rt.run()
    assert info.value.status == perma.Status.STATE
