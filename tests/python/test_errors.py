"""Failures raise the exception of their status, with libperma's message."""
import numpy as np
import pytest

import perma
from conftest import NODE

ARGUMENT = perma.Status.ARGUMENT


def check(info, status):
    """The exception pytest.raises caught carries `status` and a message."""
    assert info.value.status == status
    assert info.value.message and info.value.message == str(info.value)


def test_status_names_match_the_library():
    for status in perma.Status:
        expected = 'PERMA_OK' if status == perma.Status.OK else 'PERMA_ERR_' + status.name
        assert perma.status_name(status) == expected


def test_an_exception_class_per_status():
    for status in perma.Status:
        if status != perma.Status.OK:
            error = perma.errors.error(status, 'text')
            assert type(error) is perma.errors.ERRORS[status] and isinstance(error, perma.PermaError)
            assert error.status == status and str(error) == 'text'
            assert type(error).__name__.upper() == status.name.replace('_', '') + 'ERROR'
    unknown = perma.errors.error(99, 'from a newer libperma')
    assert type(unknown) is perma.PermaError and unknown.status == 99


def test_bad_schedule():
    with pytest.raises(perma.ArgumentError,
                       match=r"schedule 'megakernel/stealng': unknown strategy 'stealng' \(shared, stealing") as info:
        perma.Runtime('megakernel/stealng')
    check(info, ARGUMENT)
    assert isinstance(info.value, ValueError)


def test_donation_threshold_only_in_the_label():
    """The threshold is the label's /d=N, after a donating strategy only;
    there is no Runtime keyword for it."""
    with pytest.raises(perma.ArgumentError,
                       match=r"schedule 'megakernel/stealing/d=4': option '/d=4' after strategy 'stealing' "
                             r"\(/d=N only follows donation or stealing-donation\)") as info:
        perma.Runtime('megakernel/stealing/d=4')
    check(info, ARGUMENT)
    with pytest.raises(perma.ArgumentError, match=r'unknown option donation_threshold \(options: ') as info:
        perma.Runtime('megakernel/donation', donation_threshold=4)
    check(info, ARGUMENT)


def test_missing_device():
    with pytest.raises(perma.NoDeviceError, match=r"device list '7:7'.*platform 7") as info:
        perma.Runtime(device='7:7')
    check(info, perma.Status.NO_DEVICE)


def test_device_not_text():
    with pytest.raises(perma.ArgumentError, match=r"a device list is text such as '0:0', 'pocl' or 'all', "
                                                  r"not 0") as info:
        perma.Runtime(device=0)
    check(info, ARGUMENT)


def test_a_list_of_devices_for_one_runtime():
    with pytest.raises(perma.ArgumentError,
                       match=r"device '0:0/2' names 2 devices \(0:0/2.0, 0:0/2.1\); a runtime runs on one") as info:
        perma.Runtime(device='0:0/2')
    check(info, ARGUMENT)


def test_unknown_option():
    with pytest.raises(perma.ArgumentError, match=r'unknown option work_group \(options: work_groups') as info:
        perma.Runtime(work_group=2)
    check(info, ARGUMENT)


@pytest.mark.parametrize('options, message', [
    ({'work_groups': -1}, r'Runtime\(\): work_groups must be a whole number >= 0, not -1'),
    ({'group_size': 2.5}, r'Runtime\(\): group_size must be a whole number >= 0, not 2.5'),
    ({'time_limit': -1}, r'Runtime\(\): time_limit must be a number of seconds >= 0, not -1'),
    ({'build_options': 3}, r'build_options must be a string, not int'),
])
def test_bad_option_values(options, message):
    """Caught before ctypes would wrap -1 into a huge unsigned number."""
    with pytest.raises(perma.ArgumentError, match=message) as info:
        perma.Runtime(**options)
    check(info, ARGUMENT)


@pytest.fixture
def rt():
    with perma.Runtime() as runtime:
        runtime.add_type('node', NODE)
        yield runtime


def test_bad_procedure_name(rt):
    with pytest.raises(perma.ArgumentError, match=r"procedure name 'no-good' is not a C identifier") as info:
        rt.register('no-good', 'void f() {}', item=NODE, function='f')
    check(info, ARGUMENT)


def test_negative_emit_maximum(rt):
    with pytest.raises(perma.ArgumentError, match=r"procedure p: emits\['p'\] must be a whole number >= 0, "
                                                  r"not -1") as info:
        rt.register('p', 'void p() {}', item=NODE, emits={'p': -1})
    check(info, ARGUMENT)


def test_item_size_not_a_multiple_of_4(rt):
    with pytest.raises(perma.ArgumentError, match=r"procedure 'p': item_size 6 must be a multiple of 4") as info:
        rt.register('p', 'void p() {}', item=np.dtype([('a', np.uint16, (3,))]), item_type='struct odd')
    check(info, ARGUMENT)


def test_dtype_without_a_type(rt):
    with pytest.raises(perma.ArgumentError, match=r'has no OpenCL C type here: declare it with add_type') as info:
        rt.register('p', 'void p() {}', item=np.dtype([('a', np.float32)]))
    check(info, ARGUMENT)


def test_item_size_checked_against_the_device(rt):
    """The dtype says 8 bytes, the type the device compiles 4: a build error naming both."""
    rt.add_source('struct small { uint a; };', 'small.cl')
    rt.register('p', 'void p(perma_ctx *ctx, __local const struct small *s) {}', item=NODE, item_type='struct small')
    with pytest.raises(perma.BuildError, match=r"procedure 'p': item_size is 8 bytes, but sizeof\(struct small\) "
                                               r"is 4 bytes on the device") as info:
        rt.build()
    check(info, perma.Status.BUILD)


def test_compile_error_names_file_and_line(monkeypatch):
    log = []
    monkeypatch.setenv('PERMA_BUILD_LOG', '1')
    with perma.Runtime(build_log=log.append) as runtime:
        runtime.add_type('node', NODE)
        runtime.register('p', 'void p(perma_ctx *ctx, __local const struct node *n)\n{\n    undeclared(n);\n}\n',
                         item=NODE, source_file='broken.cl')
        with pytest.raises(perma.BuildError, match=r'broken\.cl:3:.*undeclared') as info:
            runtime.build()
        check(info, perma.Status.BUILD)
    assert len(log) == 1 and log[0].startswith('perma: build log (the build failed):') and 'undeclared' in log[0]


def test_python_side_checks(workloads):
    rt = workloads.rt
    cases = [
        (lambda: rt.seed(workloads.split, np.zeros(2, np.uint32)), r'seed split: the items have dtype uint32'),
        (lambda: rt.bind('leaves', np.zeros((4, 4), np.uint32)[:, 0]),
         r"buffer 'leaves': the array is not C-contiguous"),
        (lambda: rt.bind('leaves', [0]), r"buffer 'leaves': expected a numpy array, not list"),
        (lambda: rt.bind('leaves', workloads.leaves, access='rw'),
         r"access 'rw' is not one of read, write, readwrite"),
        (lambda: rt.bind('leaves', np.zeros(0, np.uint32)), r"buffer 'leaves': host memory is NULL or empty"),
    ]
    for call, message in cases:
        with pytest.raises(perma.ArgumentError, match=message) as info:
            call()
        check(info, ARGUMENT)
    frozen = np.zeros(1, np.uint32)
    frozen.flags.writeable = False
    with pytest.raises(perma.ArgumentError, match=r"buffer 'leaves': the array is read-only, but access "
                                                  r"'readwrite' writes it") as info:
        rt.bind('leaves', frozen)
    check(info, ARGUMENT)


def test_element_type_checked_against_the_dtype(workloads):
    """A type whose elements are not the array's (it was accepted, and the
    device wrote past the array's end)."""
    rt = workloads.rt
    with pytest.raises(perma.ArgumentError, match=r"buffer 'bytes': type '__global uint \*' points to uint, 4 bytes "
                                                  r"each, but the array's elements are uint8, 1 bytes each") as info:
        rt.bind('bytes', np.zeros(16, np.uint8), type='__global uint *')
    check(info, ARGUMENT)
    with pytest.raises(perma.ArgumentError, match=r"points to struct node, 8 bytes each, but the array's elements "
                                                  r"are uint32, 4 bytes each"):
        rt.bind('nodes', np.zeros(4, np.uint32), type='__global const struct node *')
    with pytest.raises(perma.ArgumentError, match=r"points to float4, 16 bytes each"):
        rt.bind('v', np.zeros(4, np.float32), type='__global float4 *')
    # Matching sizes, and a view of the bytes, bind.
    rt.bind('v', np.zeros(4, np.float32).view(np.uint32), type='__global const unsigned int *', access='read')
    rt.bind('bytes', np.zeros(16, np.uint8).view(np.uint32), type='__global uint *')


def test_reserved_buffer_name(workloads):
    with pytest.raises(perma.ArgumentError, match=r"buffer name 'kernel' is an OpenCL C keyword; choose another "
                                                  r"name") as info:
        workloads.rt.bind('kernel', np.zeros(4, np.uint32))
    check(info, ARGUMENT)


def test_emit_limit_then_the_runtime_runs_on(workloads):
    w = workloads
    w.rt.seed(w.greedy, np.array([(3, 0)], NODE))
    with pytest.raises(perma.EmitLimitError, match=r"procedure 'greedy' emitted more than its declared maximum "
                                                   r"of 1 item\(s\) into 'split'") as info:
        w.rt.run()
    check(info, perma.Status.EMIT_LIMIT)
    w.tree(6)
    assert w.leaves[0] == 64


def test_time_limit(make_workloads):
    """A chain of a billion items stops at the time limit."""
    w = make_workloads(time_limit=0.5)
    w.rt.seed(w.countdown, np.array([(1000000000, 0)], NODE))
    with pytest.raises(perma.TimeoutError, match=r'the run passed its time limit of 0.5 s') as info:
        w.rt.run()
    check(info, perma.Status.TIMEOUT)
    assert isinstance(info.value, TimeoutError)  # the built-in one too


def test_bad_reductions():
    with perma.Runtime() as rt:
        with pytest.raises(perma.ArgumentError, match=r"^reduction 'n': op 'avg' is not one of sum, min, max$") as info:
            rt.declare_reduction('n', 'avg', np.uint32)
        check(info, ARGUMENT)
        for bad in (np.uint8, np.float16, 'U4', None, np.dtype('>u4')):
            with pytest.raises(perma.ArgumentError, match=r"^reduction 'n': type .* is not one of numpy's uint32, "
                               r"int32, uint64, int64, float32 or float64$"):
                rt.declare_reduction('n', 'sum', bad)
        with pytest.raises(perma.ArgumentError, match=r"name '2n' is not a C identifier"):
            rt.declare_reduction('2n', 'sum', np.uint32)
        rt.declare_reduction('n', 'max', np.int64)
        with pytest.raises(perma.ArgumentError, match=r"reduction 'n' is already declared"):
            rt.declare_reduction('n', 'sum', np.uint32)
        with pytest.raises(perma.StateError, match=r"perma_get_reduction\('n'\): no result: no run has succeeded"
                           ) as info:
            rt.reduction('n')
        check(info, perma.Status.STATE)
        with pytest.raises(perma.ArgumentError, match=r"no reduction named 'm' is declared"):
            rt.reduction('m')
