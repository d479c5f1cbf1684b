!> Tests of mpm_stl (reading ASCII and binary STL) and of the closed-surface check and enclosed
!> volume of mpm_surface_mesh on the meshes it reads.
!>
!> The meshes are small and exact: every coordinate is a binary fraction, exact in real32 and in
!> decimal, so the ASCII and the binary form of a mesh must give bit-identical triangles, and
!> normals and areas are compared with their analytic values to round-off (10 epsilon: a few
!> products and one square root per triangle). Two committed fixtures (tests/data/stl, see its
!> README.md) are read from the repository root; every other file is written by this program as
!> raw bytes into a fresh folder under $TMPDIR (default /tmp), deleted at the end unless
!> MPM_TEST_KEEP is set.
program test_mpm_stl
    use, intrinsic :: iso_c_binding, only: c_char, c_null_char, c_int
    use, intrinsic :: iso_fortran_env, only: int32, real32
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_positive_inf
    use mpm_kinds, only: wp
    use mpm_error, only: error_type, exit_input
    use mpm_filesystem, only: remove_file, c_string
    use mpm_stl, only: read_stl
    use mpm_surface_mesh, only: stl_mesh_type, check_closed, enclosed_volume
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, check_contains, &
        finish, temporary_folder
    implicit none

    ! allow(assumed-size, assumed-size-character-intent): C strings passed to libc
    interface
        function c_rmdir(path) bind(c, name="rmdir") result(status)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: path(*)
                !! empty folder to delete, null-terminated
            integer(c_int) :: status
        end function c_rmdir

        function c_chmod(path, mode) bind(c, name="chmod") result(status)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: path(*)
                !! file, null-terminated
            integer(c_int), value :: mode
                !! new permission bits
            integer(c_int) :: status
        end function c_chmod

        function c_access(path, mode) bind(c, name="access") result(status)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: path(*)
                !! file, null-terminated
            integer(c_int), value :: mode
                !! access to test (4: read)
            integer(c_int) :: status
        end function c_access
    end interface

    character(len=*), parameter :: plane_fixture = "tests/data/stl/tilted_plane.stl"
    character(len=*), parameter :: cube_fixture = "tests/data/stl/unit_cube.stl"
    character(len=*), parameter :: key = "contact.file"
    character(len=*), parameter :: lf = achar(10), crlf = achar(13)//achar(10)
    real(wp), parameter :: tol = 10*epsilon(1.0_wp)
        !! round-off of a normal or an area computed from exact corners [-]
    ! Unit cube: corner i is (i & 1, (i >> 1) & 1, (i >> 2) & 1); 2 triangles per face, -z, +z,
    ! -y, +y, -x, +x, counter-clockwise seen from outside (as tests/data/stl/README.md).
    integer, parameter :: cube_faces(3, 12) = reshape([0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, &
        0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5], [3, 12])
    real(wp), parameter :: cube_normals(3, 6) = reshape([0.0_wp, 0.0_wp, -1.0_wp, &
        0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, -1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, &
        -1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp], [3, 6])
        !! outward normal of each face [-]

    type(test_suite_type) :: suite
    character(len=:), allocatable :: root
    character(len=256) :: written(200)
    integer :: nwritten, stat
    logical :: keep
    type(error_type), allocatable :: error

    call new_suite(suite, "mpm_stl")
    nwritten = 0
    root = temporary_folder("mpm_stl_test")
    write (*, "(a)") "temporary folder: "//root
    call get_environment_variable("MPM_TEST_KEEP", status=stat)
    keep = stat == 0

    call test_plane_fixture()
    call test_cube_fixture()
    call test_ascii_variants()
    call test_binary_solid_header()
    call test_scale_offset()
    call test_degenerate()
    call test_closed()
    call test_refusals()

    if (.not. keep) call delete_files(error)
    if (.not. keep) call check(suite, .not. allocated(error), "temporary folder deleted")
    if (allocated(error)) write (*, "(a)") error%message
    call finish(suite)

contains

    ! ----------------------------------------------------------------------------------------
    ! Meshes as bytes
    ! ----------------------------------------------------------------------------------------

    !> The unit cube as corners (coordinate, corner, triangle).
    function cube() result(vertex)
        real(wp) :: vertex(3, 3, 12)
            !! corners (coordinate, corner, triangle) [m]

        integer :: t, c, i

        do t = 1, 12
            do c = 1, 3
                i = cube_faces(c, t)
                vertex(:, c, t) = real([iand(i, 1), iand(ishft(i, -1), 1), &
                    iand(ishft(i, -2), 1)], wp)
            end do
        end do
    end function cube

    !> The tilted plane of the ASCII fixture.
    function plane() result(vertex)
        real(wp) :: vertex(3, 3, 2)
            !! corners (coordinate, corner, triangle) [m]

        vertex(:, :, 1) = reshape([0.0_wp, 0.0_wp, 0.0_wp, 2.0_wp, 0.0_wp, 1.0_wp, &
            2.0_wp, 1.0_wp, 1.25_wp], [3, 3])
        vertex(:, :, 2) = reshape([0.0_wp, 0.0_wp, 0.0_wp, 2.0_wp, 1.0_wp, 1.25_wp, &
            0.0_wp, 1.0_wp, 0.25_wp], [3, 3])
    end function plane

    !> A plain ASCII STL: one keyword group per line, zero normals, "\n" line ends.
    function ascii_text(vertex) result(text)
        real(wp), intent(in) :: vertex(:, :, :)
            !! corners (coordinate, corner, triangle) [m]
        character(len=:), allocatable :: text
            !! the file's bytes

        integer :: t, c

        text = "solid test"//lf
        do t = 1, size(vertex, 3)
            text = text//"facet normal 0 0 0"//lf//"outer loop"//lf
            do c = 1, 3
                text = text//"vertex "//number(vertex(1, c, t))//" "//number(vertex(2, c, t)) &
                    //" "//number(vertex(3, c, t))//lf
            end do
            text = text//"endloop"//lf//"endfacet"//lf
        end do
        text = text//"endsolid test"//lf
    end function ascii_text

    !> An ASCII STL in an unusual but valid layout: mixed-case keywords, tabs, several blanks,
    !> CRLF line ends, a name with blanks, a wrong normal, two solids, no final line end.
    function fancy_ascii_text(vertex) result(text)
        real(wp), intent(in) :: vertex(:, :, :)
            !! corners (coordinate, corner, triangle) [m]
        character(len=:), allocatable :: text
            !! the file's bytes

        integer :: t, c, half

        half = size(vertex, 3)/2
        text = "SOLID  my cube (part 1)"//crlf
        do t = 1, size(vertex, 3)
            if (t == half + 1) text = text//"EndSolid my cube (part 1)"//crlf//" solid"//crlf
            text = text//"  Facet"//achar(9)//"Normal 1e0 -0.0 +3.5E-1"//crlf//achar(9)// &
                "OUTER   LOOP"//crlf
            do c = 1, 3
                text = text//"   VeRtEx  "//number(vertex(1, c, t))//achar(9)// &
                    number(vertex(2, c, t))//"   "//number(vertex(3, c, t))//crlf
            end do
            text = text//"  endLOOP endfacet"//crlf
        end do
        text = text//"endsolid"
    end function fancy_ascii_text

    !> A binary STL: 80-byte header, count (default: the number of triangles), records with
    !> zero normals and attributes.
    function binary_text(vertex, header, count) result(text)
        real(wp), intent(in) :: vertex(:, :, :)
            !! corners (coordinate, corner, triangle), exact in real32 [m]
        character(len=*), intent(in) :: header
            !! header text (blank-padded to 80 bytes)
        integer, intent(in), optional :: count
            !! count to write instead of the true one (a negative one is read as 2**32 + count)
        character(len=:), allocatable :: text
            !! the file's bytes

        character(len=80) :: head
        integer :: t, c, d, n

        head = header
        n = size(vertex, 3)
        if (present(count)) n = count
        text = head//transfer(int(n, int32), "1234")
        do t = 1, size(vertex, 3)
            text = text//repeat(achar(0), 12)
            do c = 1, 3
                do d = 1, 3
                    text = text//transfer(real(vertex(d, c, t), real32), "1234")
                end do
            end do
            text = text//achar(0)//achar(0)
        end do
    end function binary_text

    !> Decimal text of an exact binary fraction (17 significant digits read back exactly).
    function number(value) result(text)
        real(wp), intent(in) :: value
            !! the number
        character(len=:), allocatable :: text
            !! "2.00000000000000000E+00"

        character(len=32) :: buffer

        write (buffer, "(es25.17)") value
        text = trim(adjustl(buffer))
    end function number

    !> Replace the nth occurrence of `old` in `text` by `new`.
    function replace(text, old, new, nth) result(changed)
        character(len=*), intent(in) :: text
            !! the original
        character(len=*), intent(in) :: old
            !! text to replace (must occur nth times)
        character(len=*), intent(in) :: new
            !! replacement
        integer, intent(in) :: nth
            !! which occurrence, from 1
        character(len=:), allocatable :: changed
            !! the text with that occurrence replaced

        integer :: i, start, found

        start = 0
        do i = 1, nth
            found = index(text(start + 1:), old)
            if (found == 0) error stop "replace: '"//old//"' not found"
            start = start + found
        end do
        changed = text(1:start - 1)//new//text(start + len(old):)
    end function replace

    !> Write `text` as the raw bytes of the file root/name; returns the path.
    function put(name, text) result(path)
        character(len=*), intent(in) :: name
            !! file name inside the temporary folder
        character(len=*), intent(in) :: text
            !! the bytes to write
        character(len=:), allocatable :: path
            !! the file's path

        integer :: unit, stat
        character(len=256) :: message

        path = root//"/"//name
        open (newunit=unit, file=path, access="stream", form="unformatted", action="write", &
            status="replace", iostat=stat, iomsg=message)
        if (stat /= 0) error stop "cannot write "//path//": "//trim(message)
        if (len(text) > 0) write (unit) text
        close (unit)
        if (all(written(1:nwritten) /= path)) then
            nwritten = nwritten + 1
            written(nwritten) = path
        end if
    end function put

    ! ----------------------------------------------------------------------------------------
    ! Comparisons
    ! ----------------------------------------------------------------------------------------

    !> Two meshes hold the same triangles, bit for bit.
    subroutine check_same(a, b, what)
        type(stl_mesh_type), intent(in) :: a
            !! first mesh
        type(stl_mesh_type), intent(in) :: b
            !! second mesh
        character(len=*), intent(in) :: what
            !! description printed on failure

        call check(suite, a%n == b%n, what//": same number of triangles")
        if (a%n /= b%n) return
        call check(suite, all(a%vertex == b%vertex), what//": same corners")
        call check(suite, all(a%normal == b%normal), what//": same normals")
        call check(suite, all(a%area == b%area), what//": same areas")
        call check(suite, all(a%lo == b%lo) .and. all(a%hi == b%hi), what//": same box")
    end subroutine check_same

    !> A mesh is the unit cube in its table order, scaled by `s` and moved by `shift`.
    subroutine check_cube(mesh, s, shift, what)
        type(stl_mesh_type), intent(in) :: mesh
            !! mesh read
        real(wp), intent(in) :: s
            !! scale it was read with [-]
        real(wp), intent(in) :: shift(3)
            !! offset it was read with [m]
        character(len=*), intent(in) :: what
            !! description printed on failure

        real(wp) :: expected(3, 3, 12)
        integer :: t, c

        call check(suite, mesh%n == 12, what//": 12 triangles")
        if (mesh%n /= 12) return
        expected = cube()
        do t = 1, 12
            do c = 1, 3
                expected(:, c, t) = expected(:, c, t)*s + shift
            end do
        end do
        call check(suite, all(mesh%vertex == expected), what//": corners x*scale + offset")
        do t = 1, 12
            call check_close(suite, maxval(abs(mesh%normal(:, t) - &
                cube_normals(:, (t + 1)/2))), 0.0_wp, tol, what//": outward unit normal")
            call check_close(suite, mesh%area(t), 0.5_wp*s**2, tol*s**2, what//": area")
        end do
        call check(suite, all(mesh%lo == shift) .and. all(mesh%hi == shift + s), &
            what//": bounding box")
        call check(suite, all(mesh%source == [(t, t=1, 12)]), what//": file numbers")
        call check(suite, mesh%skipped == 0, what//": nothing skipped")
    end subroutine check_cube

    ! ----------------------------------------------------------------------------------------
    ! Tests
    ! ----------------------------------------------------------------------------------------

    !> The committed ASCII plane: recomputed normals, areas, box; the binary form is the same.
    subroutine test_plane_fixture()
        type(stl_mesh_type) :: mesh, binary
        type(error_type), allocatable :: error
        real(wp) :: normal(3)
        integer :: t

        call read_stl(plane_fixture, mesh, error, key=key)
        call check(suite, .not. allocated(error), "plane fixture read")
        if (allocated(error)) then
            write (*, "(a)") error%message
            return
        end if
        call check(suite, mesh%n == 2 .and. .not. mesh%binary, "plane: 2 triangles, ASCII")
        call check(suite, all(mesh%vertex == plane()), "plane: corners as in the file")
        ! z = 0.5 x + 0.25 y: upward normal (-0.5, -0.25, 1)/|.|, the file says (0, 0, -1)
        normal = [-0.5_wp, -0.25_wp, 1.0_wp]/sqrt(1.3125_wp)
        do t = 1, 2
            call check_close(suite, maxval(abs(mesh%normal(:, t) - normal)), 0.0_wp, tol, &
                "plane: normal from the corner order, not from the file")
            ! area of the plane over [0,2]x[0,1] is 2 sqrt(1 + 0.5**2 + 0.25**2), half each
            call check_close(suite, mesh%area(t), sqrt(1.3125_wp), tol, "plane: area")
        end do
        call check(suite, all(mesh%lo == [0.0_wp, 0.0_wp, 0.0_wp]) .and. &
            all(mesh%hi == [2.0_wp, 1.0_wp, 1.25_wp]), "plane: bounding box")

        call read_stl(put("plane.stl", binary_text(plane(), "plane")), binary, error)
        call check(suite, .not. allocated(error), "plane: binary read")
        call check(suite, binary%binary, "plane: binary detected")
        call check_same(mesh, binary, "plane ASCII vs binary")
    end subroutine test_plane_fixture

    !> The committed binary cube, against the ASCII cube written here.
    subroutine test_cube_fixture()
        type(stl_mesh_type) :: mesh, ascii
        type(error_type), allocatable :: error
        logical :: closed
        character(len=:), allocatable :: message

        call read_stl(cube_fixture, mesh, error, key=key)
        call check(suite, .not. allocated(error), "cube fixture read")
        if (allocated(error)) then
            write (*, "(a)") error%message
            return
        end if
        call check(suite, mesh%binary, "cube fixture: binary")
        call check_cube(mesh, 1.0_wp, [0.0_wp, 0.0_wp, 0.0_wp], "cube fixture")
        call check_closed(mesh, closed, message, error)
        call check(suite, .not. allocated(error) .and. closed, "cube fixture closed: "//message)
        call check_contains(suite, message, "closed and consistently oriented", "closed text")
        ! outward normals: the divergence theorem gives +1 m3
        call check_close(suite, enclosed_volume(mesh), 1.0_wp, tol, "cube volume")

        call read_stl(put("cube_ascii.stl", ascii_text(cube())), ascii, error)
        call check(suite, .not. allocated(error), "cube ASCII read")
        call check(suite, .not. ascii%binary, "cube ASCII detected")
        call check_same(mesh, ascii, "cube binary vs ASCII")
    end subroutine test_cube_fixture

    !> Unusual ASCII layouts, a byte order mark, and no key give the same triangles.
    subroutine test_ascii_variants()
        type(stl_mesh_type) :: reference, mesh
        type(error_type), allocatable :: error

        call read_stl(cube_fixture, reference, error)
        call check(suite, .not. allocated(error), "cube fixture without key")
        call read_stl(root//"/missing.stl", mesh, error)
        call check(suite, allocated(error), "missing file without key: refused")
        if (allocated(error)) call check_contains(suite, error%message, 'STL file "'//root// &
            '/missing.stl": the file does not exist', "missing file without key: message")

        call read_stl(put("fancy.stl", fancy_ascii_text(cube())), mesh, error)
        call check(suite, .not. allocated(error), "fancy ASCII read")
        if (allocated(error)) write (*, "(a)") error%message
        call check_same(reference, mesh, "fancy ASCII (case, tabs, CRLF, 2 solids)")

        call read_stl(put("bom.stl", char(239)//char(187)//char(191)//ascii_text(cube())), &
            mesh, error)
        call check(suite, .not. allocated(error), "ASCII with a UTF-8 byte order mark read")
        call check_same(reference, mesh, "ASCII with a byte order mark")
    end subroutine test_ascii_variants

    !> A binary file whose header starts with "solid" is binary (decided by its size).
    subroutine test_binary_solid_header()
        type(stl_mesh_type) :: reference, mesh
        type(error_type), allocatable :: error

        call read_stl(cube_fixture, reference, error)
        call read_stl(put("solid_binary.stl", binary_text(cube(), "solid cube")), mesh, error, &
            key=key)
        call check(suite, .not. allocated(error), "binary with 'solid' header read")
        if (allocated(error)) write (*, "(a)") error%message
        call check(suite, mesh%binary, "binary with 'solid' header detected as binary")
        call check_same(reference, mesh, "binary with 'solid' header")
    end subroutine test_binary_solid_header

    !> x*scale + offset, in both formats; normals unchanged, areas times scale**2.
    subroutine test_scale_offset()
        type(stl_mesh_type) :: mesh, ascii
        type(error_type), allocatable :: error
        real(wp), parameter :: shift(3) = [10.0_wp, -5.0_wp, 100.0_wp]
        logical :: closed
        character(len=:), allocatable :: message

        call read_stl(cube_fixture, mesh, error, scale=2.0_wp, offset=shift, key=key)
        call check(suite, .not. allocated(error), "scaled cube read")
        call check_cube(mesh, 2.0_wp, shift, "scaled and moved cube")
        call check_close(suite, enclosed_volume(mesh), 8.0_wp, 8*tol, "scaled cube volume")
        call check_closed(mesh, closed, message, error)
        call check(suite, closed, "scaled cube closed")

        call read_stl(put("cube_ascii.stl", ascii_text(cube())), ascii, error, scale=2.0_wp, &
            offset=shift)
        call check_same(mesh, ascii, "scaled cube, binary vs ASCII")

        call read_stl(cube_fixture, mesh, error, scale=1.0e-3_wp)
        call check(suite, .not. allocated(error), "cube in millimetres read")
        call check_close(suite, mesh%hi(3), 1.0e-3_wp, 0.0_wp, "millimetres: box")
        call check_close(suite, mesh%area(1), 0.5e-6_wp, 0.5e-6_wp*tol, "millimetres: area")
    end subroutine test_scale_offset

    !> Zero-area triangles are skipped and counted; the rest keeps its file numbers.
    subroutine test_degenerate()
        type(stl_mesh_type) :: mesh, ascii
        type(error_type), allocatable :: error
        real(wp) :: vertex(3, 3, 14)
        logical :: closed
        character(len=:), allocatable :: message
        integer :: t

        ! cube triangles 1-2, a repeated corner, cube 3-8, three collinear corners, cube 9-12
        vertex(:, :, 1:2) = reshape(cube(), [3, 3, 2])
        vertex(:, :, 3) = reshape([0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 1.0_wp, 1.0_wp, &
            0.0_wp, 0.0_wp, 0.0_wp], [3, 3])
        vertex(:, :, 4:9) = cube_part(3, 8)
        vertex(:, :, 10) = reshape([0.0_wp, 0.0_wp, 0.0_wp, 0.5_wp, 0.25_wp, 0.125_wp, &
            1.0_wp, 0.5_wp, 0.25_wp], [3, 3])
        vertex(:, :, 11:14) = cube_part(9, 12)

        call read_stl(put("degenerate.stl", binary_text(vertex, "degenerate")), mesh, error)
        call check(suite, .not. allocated(error), "degenerate: read")
        call check(suite, mesh%n == 12 .and. mesh%skipped == 2, "degenerate: 2 skipped")
        call check(suite, all(mesh%source == [1, 2, (t, t=4, 9), (t, t=11, 14)]), &
            "degenerate: file numbers of the triangles kept")
        call check(suite, all(mesh%vertex == cube()), "degenerate: the cube is left")
        call check(suite, size(mesh%area) == 12 .and. size(mesh%vertex, 3) == 12, &
            "degenerate: arrays trimmed to n")
        call check_closed(mesh, closed, message, error)
        call check(suite, closed, "degenerate: the cube left is closed")

        call read_stl(put("degenerate_ascii.stl", ascii_text(vertex)), ascii, error)
        call check(suite, ascii%n == 12 .and. ascii%skipped == 2, "degenerate ASCII: 2 skipped")
        call check_same(mesh, ascii, "degenerate, binary vs ASCII")
    end subroutine test_degenerate

    !> Cube triangles first..last.
    function cube_part(first, last) result(vertex)
        integer, intent(in) :: first
            !! first triangle
        integer, intent(in) :: last
            !! last triangle
        real(wp), allocatable :: vertex(:, :, :)
            !! their corners (coordinate, corner, triangle) [m]

        real(wp) :: all_triangles(3, 3, 12)

        all_triangles = cube()
        vertex = all_triangles(:, :, first:last)
    end function cube_part

    !> Closed, open, inconsistently oriented, non-manifold and inside-out cubes.
    subroutine test_closed()
        type(stl_mesh_type) :: mesh
        type(error_type), allocatable :: error
        real(wp) :: vertex(3, 3, 13), corner(3)
        logical :: closed
        character(len=:), allocatable :: message
        integer :: t

        ! minus triangle 5 (y = 0 face): its 3 edges belong to one triangle each
        vertex(:, :, 1:4) = cube_part(1, 4)
        vertex(:, :, 5:11) = cube_part(6, 12)
        call read_stl(put("open.stl", binary_text(vertex(:, :, 1:11), "open")), mesh, error)
        call check_closed(mesh, closed, message, error)
        call check(suite, .not. allocated(error) .and. .not. closed, "open cube is not closed")
        call check_contains(suite, message, "belongs to 1 triangle", "open: edge of 1 triangle")
        call check_contains(suite, message, "the surface is open", "open: says open")
        call check_contains(suite, message, "3 edges belong to one triangle only", &
            "open: counts the 3 boundary edges")
        call check_contains(suite, message, "edge from (", "open: names the edge")
        write (*, "(a)") "open cube: "//message

        ! triangle 7 (y = 1 face) with two corners swapped
        vertex(:, :, 1:12) = cube()
        corner = vertex(:, 2, 7)
        vertex(:, 2, 7) = vertex(:, 3, 7)
        vertex(:, 3, 7) = corner
        call read_stl(put("flipped.stl", binary_text(vertex(:, :, 1:12), "flipped")), mesh, &
            error)
        call check_closed(mesh, closed, message, error)
        call check(suite, .not. closed, "flipped triangle: not closed")
        call check_contains(suite, message, "inconsistently oriented", "flipped: orientation")
        call check_contains(suite, message, "one of them is flipped", "flipped: says flipped")
        call check_contains(suite, message, "7", "flipped: names triangle 7")
        call check_contains(suite, message, "3 edges have this problem", "flipped: 3 edges")
        write (*, "(a)") "flipped triangle: "//message

        ! a triangle repeated: its edges belong to 3 triangles
        vertex(:, :, 1:12) = cube()
        vertex(:, :, 13) = vertex(:, :, 1)
        call read_stl(put("repeated.stl", binary_text(vertex, "repeated")), mesh, error)
        call check_closed(mesh, closed, message, error)
        call check(suite, .not. closed, "repeated triangle: not closed")
        call check_contains(suite, message, "not a manifold", "repeated: not a manifold")
        call check_contains(suite, message, "shared by 3 triangles", "repeated: 3 triangles")

        ! every triangle flipped: closed and consistent, but inside out (volume -1)
        vertex(:, :, 1:12) = cube()
        do t = 1, 12
            corner = vertex(:, 2, t)
            vertex(:, 2, t) = vertex(:, 3, t)
            vertex(:, 3, t) = corner
        end do
        call read_stl(put("inside_out.stl", binary_text(vertex(:, :, 1:12), "inside out")), &
            mesh, error)
        call check_closed(mesh, closed, message, error)
        call check(suite, closed, "inside-out cube: closed and consistent")
        call check_close(suite, enclosed_volume(mesh), -1.0_wp, tol, "inside-out: volume -1")

        ! an open terrain: the plane
        call read_stl(plane_fixture, mesh, error)
        call check_closed(mesh, closed, message, error)
        call check(suite, .not. closed, "plane: open")
        call check_contains(suite, message, "4 edges belong to one triangle only", &
            "plane: 4 boundary edges")
    end subroutine test_closed

    !> Every refusal: exit_input, the file and the key in the message, and why.
    subroutine test_refusals()
        character(len=:), allocatable :: ascii, binary, path, text
        real(wp) :: nan, inf
        real(wp) :: vertex(3, 3, 2)
        character(len=4) :: bits
        integer :: cut

        ascii = ascii_text(plane())
        binary = binary_text(cube(), "cube")

        ! the file itself
        call expect_refusal(root//"/missing.stl", ["the file does not exist"], "missing")
        call expect_refusal(root, ["it is a folder, not a file"], "folder")
        path = put("unreadable.stl", ascii)
        if (c_chmod(c_string(path), 0_c_int) == 0 .and. c_access(c_string(path), 4_c_int) /= 0) &
            then
            call expect_refusal(path, ["cannot be opened"], "unreadable")
        else
            write (*, "(a)") "note: running as root, the unreadable file is readable: not tested"
        end if
        call expect_refusal(put("empty.stl", ""), ["the file is empty"], "empty")

        ! binary of the wrong size
        call expect_refusal(put("truncated.stl", binary(1:len(binary) - 10)), [character(60) :: &
            "binary STL of the wrong size", "announces 12 triangles", &
            "84 + 50 x 12 = 684 bytes", "the file has 674 bytes (truncated?)"], "truncated binary")
        text = binary_text(cube(), "solid cube")
        call expect_refusal(put("truncated_solid.stl", text(1:500)), [character(60) :: &
            "binary STL of the wrong size", "the file has 500 bytes (truncated?)"], &
            "truncated binary starting with 'solid'")
        call expect_refusal(put("long.stl", binary//"extra"), [character(80) :: &
            "the file has 689 bytes (extra bytes after the last triangle?)"], "binary too long")
        call expect_refusal(put("huge_count.stl", binary_text(cube(), "cube", count=-2)), &
            [character(60) :: "announces 4294967294 triangles"], "count as unsigned 32 bits")
        call expect_refusal(put("stub.stl", achar(0)//achar(1)//"abc"), [character(60) :: &
            "only 5 bytes, less than the 84 bytes"], "binary shorter than a header")

        ! ASCII truncated or garbled (plain layout: facet 2 is on lines 9-15)
        cut = index(ascii, "endloop", back=.true.)
        call expect_refusal(put("cut.stl", ascii(1:cut - 1)), [character(80) :: &
            "line 13: the file ends where 'endloop' was expected (truncated?)"], "ASCII cut")
        cut = index(ascii, "endsolid")
        call expect_refusal(put("no_end.stl", ascii(1:cut - 1)), [character(60) :: &
            "the file ends before 'endsolid' (truncated?)"], "ASCII without endsolid")
        call expect_refusal(put("vertx.stl", replace(ascii, "vertex", "vertx", 5)), &
            [character(60) :: "line 12: expected 'vertex', found 'vertx'"], "ASCII misspelt")
        call expect_refusal(put("bad_number.stl", replace(ascii, "2.00000000000000000E+00", &
            "2.0.0", 1)), [character(80) :: "line 5: expected a number (coordinate x of " &
            //"vertex 2 of facet 1), found '2.0.0'"], "ASCII bad number")
        call expect_refusal(put("short_vertex.stl", replace(ascii, " 1.25000000000000000E+00" &
            //lf, lf, 1)), [character(80) :: "line 7: expected a number (coordinate z of " &
            //"vertex 3 of facet 1), found 'endloop'"], "ASCII vertex of 2 numbers")
        call expect_refusal(put("text.stl", "hello world"//lf), [character(60) :: &
            "line 1: expected 'solid'", "found 'hello'"], "text that is not STL")
        call expect_refusal(put("trailing.stl", ascii//"facet"//lf), [character(80) :: &
            "line 17: expected 'solid' or the end of the file after 'endsolid', " &
            //"found 'facet'"], "ASCII after endsolid")
        call expect_refusal(put("huge_number.stl", replace(ascii, "2.00000000000000000E+00", &
            "1e400", 1)), [character(60) :: "line 5: the number '1e400'", "out of range"], &
            "ASCII number out of range")

        ! zero triangles
        text = binary_text(cube(), "zero", count=0)
        call expect_refusal(put("zero.stl", text(1:84)), &
            [character(60) :: "zero triangles: the file holds no triangle"], "binary of 0")
        call expect_refusal(put("zero_ascii.stl", "solid nothing"//lf//"endsolid nothing"//lf), &
            [character(60) :: "zero triangles: the file holds no triangle"], "ASCII of 0")
        vertex = 0.0_wp
        vertex(1, 2, :) = 1.0_wp
        call expect_refusal(put("all_degenerate.stl", binary_text(vertex, "degenerate")), &
            [character(60) :: "zero triangles: all 2 triangles are degenerate"], &
            "all degenerate")

        ! NaN and infinity (bit patterns: a real32 NaN is never computed here)
        bits = transfer(int(z'7FC00000', int32), bits)
        call expect_refusal(put("nan.stl", binary(1:84 + 50*4 + 12 + 4)//bits// &
            binary(84 + 50*4 + 12 + 9:)), [character(60) :: &
            "triangle 5 has a NaN or infinite coordinate (corner 1, y)"], "binary NaN")
        bits = transfer(int(z'FF800000', int32), bits)
        call expect_refusal(put("inf.stl", binary(1:84 + 50*11 + 44)//bits// &
            binary(84 + 50*11 + 49:)), [character(60) :: &
            "triangle 12 has a NaN or infinite coordinate (corner 3, z)"], "binary -Inf")
        call expect_refusal(put("nan_ascii.stl", replace(ascii, "1.25000000000000000E+00", &
            "NaN", 2)), [character(80) :: "line 12: triangle 2 has a NaN or infinite " &
            //"coordinate (corner 2, z: 'NaN')"], "ASCII NaN")
        call expect_refusal(put("inf_ascii.stl", replace(ascii, "1.00000000000000000E+00", &
            "-inf", 1)), [character(60) :: "triangle 1 has a NaN or infinite"], "ASCII -inf")

        ! coordinates too large for the arithmetic
        call expect_refusal(put("far.stl", replace(ascii, "2.00000000000000000E+00", &
            "1e35", 1)), [character(80) :: "line 2: triangle 1 has the coordinate 1.0E+35 " &
            //"(corner 2, x), beyond 1.0E+30 m", "(wrong units?)"], "coordinate beyond the limit")

        ! scale
        nan = ieee_value(nan, ieee_quiet_nan)
        inf = ieee_value(inf, ieee_positive_inf)
        call expect_refusal(cube_fixture, ["the scale must be > 0, not 0"], "scale 0", &
            scale=0.0_wp)
        call expect_refusal(cube_fixture, ["the scale must be > 0, not -1"], "scale -1", &
            scale=-1.0_wp)
        call expect_refusal(cube_fixture, ["the scale must be a finite number > 0"], &
            "scale NaN", scale=nan)
        call expect_refusal(cube_fixture, ["the scale must be a finite number > 0"], &
            "scale Inf", scale=inf)
        call expect_refusal(cube_fixture, ["the offset must be 3 finite numbers"], &
            "offset NaN", offset=[0.0_wp, nan, 0.0_wp])
    end subroutine test_refusals

    !> read_stl refuses `path` with exit_input, a message naming the file and the key, and
    !> containing every part.
    subroutine expect_refusal(path, parts, what, scale, offset)
        character(len=*), intent(in) :: path
            !! file to read
        character(len=*), intent(in) :: parts(:)
            !! texts the message must contain (trailing blanks ignored)
        character(len=*), intent(in) :: what
            !! description printed on failure
        real(wp), intent(in), optional :: scale
            !! scale passed to read_stl [-]
        real(wp), intent(in), optional :: offset(3)
            !! offset passed to read_stl [m]

        type(stl_mesh_type) :: mesh
        type(error_type), allocatable :: error
        integer :: i

        call read_stl(path, mesh, error, scale=scale, offset=offset, key=key)
        call check(suite, allocated(error), what//": refused")
        if (.not. allocated(error)) return
        call check(suite, error%code == exit_input, what//": exit_input")
        call check(suite, mesh%n == 0, what//": no triangles")
        call check_contains(suite, error%message, key//' = "'//path//'"', what//": file and key")
        do i = 1, size(parts)
            call check_contains(suite, error%message, trim(parts(i)), what)
        end do
        write (*, "(a)") "  "//what//": "//error%message
    end subroutine expect_refusal

    ! ----------------------------------------------------------------------------------------
    ! Temporary folder
    ! ----------------------------------------------------------------------------------------

    !> Delete the files this test wrote, then the folder.
    subroutine delete_files(error)
        type(error_type), allocatable, intent(out) :: error
            !! set when a file or the folder cannot be deleted

        integer :: i

        do i = 1, nwritten
            call remove_file(trim(written(i)), error)
            if (allocated(error)) return
        end do
        if (c_rmdir(c_string(root)) /= 0) then
            allocate (error)
            error%message = "cannot remove the folder "//root
        end if
    end subroutine delete_files

end program test_mpm_stl
