!> Fill the bodies of a case with particles.
module mpm_bodies
    use mpm_kinds, only: wp, i8
    use mpm_error, only: error_type, fatal_error, exit_other
    use mpm_case, only: case_type, body_subcell_range, dist_random
    use mpm_particles, only: particles_type, new_particles
    implicit none
    private
    public :: count_body_particles, create_particles, body_cell_histogram

    !> The sites (sub-cells) of a body and which of them hold a particle.
    type :: sites_type
        integer :: lo(3) = 0
            !! first sub-cell along each axis
        integer :: hi(3) = 0
            !! last sub-cell along each axis
        logical, allocatable :: inside(:, :, :)
            !! site holds a particle (STL body only; a box holds all its sites)
    end type sites_type

    ! Shift of the test line off the particle, in sub-cells along the two axes across it:
    ! irrational fractions, so the line never meets an edge or a corner of a mesh whose
    ! coordinates are round numbers.
    real(wp), parameter :: shift_u = 1.0e-7_wp*sqrt(2.0_wp)
    real(wp), parameter :: shift_v = 1.0e-7_wp*sqrt(3.0_wp)

contains

    !> Number of particles body b holds: every site of its sub-cell range for a box, the sites
    !> inside the closed surface for an STL body (see body_sites); -1 when the memory to test
    !> the sites of an STL body cannot be allocated.
    integer(i8) function count_body_particles(case, b)
        type(case_type), intent(in) :: case
            !! resolved case (bodies 1..b set)
        integer, intent(in) :: b
            !! body index

        integer :: lo(3), hi(3), a, first
        logical, allocatable :: inside(:, :, :)
        type(error_type), allocatable :: error

        call body_sites(case, b, lo, hi, first, inside, error)
        if (allocated(error)) then
            count_body_particles = -1_i8
        else if (allocated(inside)) then
            count_body_particles = count(inside, kind=i8)
        else
            count_body_particles = 1_i8
            do a = 1, case%dim
                count_body_particles = count_body_particles*int(max(0, hi(a) - lo(a) + 1), i8)
            end do
        end if
    end function count_body_particles

    !> Create the particles of every body: positions, volumes, masses, velocities, sizes.
    !>
    !> With `slab`, only the particles whose cell along axis slab(1) is in [slab(2), slab(3))
    !> (an image's part of the grid, mpm_decomposition), numbered in particles%id by their
    !> index among all particles.
    subroutine create_particles(case, particles, error, nstate, slab)
        type(case_type), intent(in) :: case
            !! resolved case
        type(particles_type), intent(out) :: particles
            !! the particles, body by body in case order
        type(error_type), allocatable, intent(out) :: error
            !! set when memory cannot be allocated
        integer, intent(in), optional :: nstate
            !! material state variables per particle (default 0)
        integer, intent(in), optional :: slab(3)
            !! axis, first cell, one past the last cell of the particles to keep

        integer :: b, a, p, q, n, s(3), i, j, k, dim, pass, stat, first
        integer(i8) :: total
        integer :: lo(3), hi(3)
        real(wp) :: h, vol, x(3)
        character(len=256) :: msg
        type(sites_type), allocatable :: sites(:)

        dim = case%dim
        ! the sites of every body, tested once for the count and for both passes
        allocate (sites(size(case%bodies)))
        total = 0
        do b = 1, size(case%bodies)
            call body_sites(case, b, sites(b)%lo, sites(b)%hi, first, sites(b)%inside, error)
            if (allocated(error)) return
            if (allocated(sites(b)%inside)) then
                total = total + count(sites(b)%inside, kind=i8)
            else
                total = total + product(int(max(0, sites(b)%hi(1:dim) - sites(b)%lo(1:dim) &
                    + 1), i8))
            end if
        end do
        h = case%dx/real(case%ppc, wp)
        vol = h**dim
        if (.not. present(slab)) then
            call new_particles(particles, dim, int(total), error, nstate)
            if (allocated(error)) return
        end if
        ! with a slab: count the particles kept, then create them
        do pass = 1, merge(2, 1, present(slab))
            if (pass == 2) then
                call new_particles(particles, dim, q, error, nstate)
                if (allocated(error)) return
                allocate (particles%id(q), stat=stat, errmsg=msg)
                if (stat /= 0) then
                    call fatal_error(error, "cannot allocate the particle ids: "//trim(msg), &
                        exit_other)
                    return
                end if
            end if
            n = 0
            p = 0
            q = 0
            do b = 1, size(case%bodies)
                associate (body => case%bodies(b), &
                           rho => case%materials(case%bodies(b)%material)%density)
                    lo = sites(b)%lo
                    hi = sites(b)%hi
                    do k = lo(3), hi(3)
                        do j = lo(2), hi(2)
                            do i = lo(1), hi(1)
                                ! n numbers the sites (it seeds the jitter), p the particles
                                n = n + 1
                                if (allocated(sites(b)%inside)) then
                                    if (.not. sites(b)%inside(i, j, k)) cycle
                                end if
                                p = p + 1
                                s = [i, j, k]
                                x = particle_position(case, s, n, h)
                                if (present(slab)) then
                                    a = global_cell_of(case, x(slab(1)), slab(1))
                                    if (a < slab(2) .or. a >= slab(3)) cycle
                                end if
                                q = q + 1
                                if (present(slab) .and. pass == 1) cycle
                                if (present(slab)) particles%id(q) = p
                                particles%x(:, q) = x(1:dim)
                                particles%v(:, q) = body%velocity(1:dim)
                                particles%volume(q) = vol
                                particles%volume0(q) = vol
                                particles%mass(q) = rho*vol
                                particles%lp0(:, q) = 0.5_wp*h
                                particles%lp(:, q) = 0.5_wp*h
                                particles%material(q) = body%material
                            end do
                        end do
                    end do
                end associate
            end do
        end do
    end subroutine create_particles

    !> Particles per cell layer along axis a, of all the particles the bodies hold.
    subroutine body_cell_histogram(case, a, histogram)
        type(case_type), intent(in) :: case
            !! resolved case
        integer, intent(in) :: a
            !! axis
        integer(i8), intent(out) :: histogram(0:)
            !! particles per cell layer (0 : ncells(a) - 1)

        integer :: b, n, s(3), i, j, k, lo(3), hi(3), c, first
        real(wp) :: h, x(3)
        logical, allocatable :: inside(:, :, :)
        type(error_type), allocatable :: error

        histogram = 0
        h = case%dx/real(case%ppc, wp)
        n = 0
        do b = 1, size(case%bodies)
            ! out of memory: every site of the bounding box counts (only the balance suffers;
            ! create_particles then reports the error)
            call body_sites(case, b, lo, hi, first, inside, error)
            do k = lo(3), hi(3)
                do j = lo(2), hi(2)
                    do i = lo(1), hi(1)
                        n = n + 1
                        if (allocated(inside)) then
                            if (.not. inside(i, j, k)) cycle
                        end if
                        s = [i, j, k]
                        x = particle_position(case, s, n, h)
                        c = global_cell_of(case, x(a), a)
                        histogram(c) = histogram(c) + 1
                    end do
                end do
            end do
        end do
    end subroutine body_cell_histogram

    !> Sites (sub-cells, see body_subcell_range) of body b and, for an STL body, which of
    !> them hold a particle.
    !>
    !> A site of an STL body holds a particle when its particle position lies inside the closed
    !> surface: an odd number of the surface's crossings with a line through the position lie
    !> below it. The line is parallel to z through (x, y) in 3D; in 2D the body is the section
    !> of the surface by z = 0 and the line is parallel to y through (x, 0). The crossings are
    !> gathered column by column (a column is the sub-cells with the same x, and the same y in
    !> 3D): each triangle visits only the columns its projected bounding box covers.
    subroutine body_sites(case, b, lo, hi, first, inside, error)
        type(case_type), intent(in) :: case
            !! resolved case (bodies 1..b set)
        integer, intent(in) :: b
            !! body index
        integer, intent(out) :: lo(3)
            !! first sub-cell of the body along each axis
        integer, intent(out) :: hi(3)
            !! last sub-cell of the body along each axis
        integer, intent(out) :: first
            !! sites of the bodies before b (numbers the jitter of the random distribution)
        logical, allocatable, intent(out) :: inside(:, :, :)
            !! (lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)) site holds a particle; not allocated
            !! for a box, whose sites all hold one
        type(error_type), allocatable, intent(out) :: error
            !! set when memory cannot be allocated

        integer :: c, l(3), u(3), stat
        character(len=256) :: msg

        first = 0
        do c = 1, b - 1
            call body_subcell_range(case, case%bodies(c), l, u)
            first = first + product(max(0, u(1:case%dim) - l(1:case%dim) + 1))
        end do
        call body_subcell_range(case, case%bodies(b), lo, hi)
        if (.not. allocated(case%bodies(b)%triangle)) return
        allocate (inside(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)), stat=stat, errmsg=msg)
        if (stat /= 0) then
            call fatal_error(error, "cannot allocate the sites of body '" &
                //case%bodies(b)%name//"': "//trim(msg), exit_other)
            return
        end if
        inside = .false.
        if (any(hi(1:case%dim) < lo(1:case%dim))) return
        call fill_surface(case, case%bodies(b)%triangle, lo, hi, first, inside, error)
    end subroutine body_sites

    !> Mark the sites whose particle lies inside a closed surface (see body_sites).
    subroutine fill_surface(case, triangle, lo, hi, first, inside, error)
        type(case_type), intent(in) :: case
            !! resolved case
        real(wp), intent(in) :: triangle(:, :, :)
            !! corners (coordinate, corner, triangle) of the closed surface [m]
        integer, intent(in) :: lo(3)
            !! first sub-cell along each axis
        integer, intent(in) :: hi(3)
            !! last sub-cell along each axis
        integer, intent(in) :: first
            !! sites of the bodies before this one
        logical, intent(inout) :: inside(lo(1):, lo(2):, lo(3):)
            !! site holds a particle (false on entry)
        type(error_type), allocatable, intent(out) :: error
            !! set when memory cannot be allocated

        integer :: va, wa, nu, nv, ncol, t, iu, iv, c, m, s(3), n, k, stat, below
        integer :: range(2, 2)
        integer, allocatable :: start(:), fill(:), member(:)
        real(wp), allocatable :: crossing(:)
        real(wp) :: h, x(3), point(2), last(2)
        character(len=256) :: msg

        ! u = x; v and w: the axes across and along the line
        va = merge(2, 3, case%dim == 3)
        wa = merge(3, 2, case%dim == 3)
        h = case%dx/real(case%ppc, wp)
        nu = hi(1) - lo(1) + 1
        nv = 1
        if (case%dim == 3) nv = hi(2) - lo(2) + 1
        ncol = nu*nv
        allocate (start(ncol + 1), fill(ncol), stat=stat, errmsg=msg)
        if (stat /= 0) then
            call fatal_error(error, "cannot allocate the columns of a body: "//trim(msg), &
                exit_other)
            return
        end if
        ! columns covered by each triangle: count, then list (compressed rows)
        start = 0
        do t = 1, size(triangle, 3)
            if (.not. covered(t, range)) cycle
            do iv = range(1, 2), range(2, 2)
                do iu = range(1, 1), range(2, 1)
                    c = column(iu, iv)
                    start(c + 1) = start(c + 1) + 1
                end do
            end do
        end do
        start(1) = 1
        do c = 1, ncol
            start(c + 1) = start(c + 1) + start(c)
        end do
        allocate (member(start(ncol + 1) - 1), crossing(maxval(start(2:) - start(:ncol)) + 1), &
            stat=stat, errmsg=msg)
        if (stat /= 0) then
            call fatal_error(error, "cannot allocate the crossings of a body: "//trim(msg), &
                exit_other)
            return
        end if
        fill = start(1:ncol)
        do t = 1, size(triangle, 3)
            if (.not. covered(t, range)) cycle
            do iv = range(1, 2), range(2, 2)
                do iu = range(1, 1), range(2, 1)
                    c = column(iu, iv)
                    member(fill(c)) = t
                    fill(c) = fill(c) + 1
                end do
            end do
        end do
        ! the sites of each column, bottom up; crossings recomputed when the line moves
        ! (with the random distribution every particle has its own line)
        do iv = merge(lo(2), 0, case%dim == 3), merge(hi(2), 0, case%dim == 3)
            do iu = lo(1), hi(1)
                c = column(iu, iv)
                last = huge(1.0_wp)
                m = 0
                do k = lo(wa), hi(wa)
                    s = 0
                    s(1) = iu
                    s(wa) = k
                    if (case%dim == 3) s(2) = iv
                    n = first + 1 + (s(1) - lo(1)) + nu*((s(2) - lo(2)) &
                        + (hi(2) - lo(2) + 1)*(s(3) - lo(3)))
                    x = particle_position(case, s, n, h)
                    point = [x(1) + shift_u*h, shift_v*h]
                    if (case%dim == 3) point(2) = point(2) + x(2)
                    if (any(point /= last)) then
                        call column_crossings(point, c, m)
                        last = point
                    end if
                    below = count(crossing(1:m) < x(wa))
                    inside(s(1), s(2), s(3)) = modulo(below, 2) == 1
                end do
            end do
        end do

    contains

        !> Column number (1-based) of sub-cell column (iu, iv).
        pure integer function column(iu, iv)
            integer, intent(in) :: iu
                !! sub-cell along x
            integer, intent(in) :: iv
                !! sub-cell along y (3D), 0 (2D)
            column = iu - lo(1) + 1
            if (case%dim == 3) column = column + nu*(iv - lo(2))
        end function column

        !> Whether triangle t's projection can meet a column line, and the columns it covers.
        logical function covered(t, range)
            integer, intent(in) :: t
                !! triangle
            integer, intent(out) :: range(2, 2)
                !! first and last column along u (:, 1) and v (:, 2)

            real(wp) :: box(2, 2)

            box(1, 1) = minval(triangle(1, :, t))
            box(2, 1) = maxval(triangle(1, :, t))
            box(1, 2) = minval(triangle(va, :, t))
            box(2, 2) = maxval(triangle(va, :, t))
            range(1, 1) = max(lo(1), floor((box(1, 1) - case%origin(1))/h))
            range(2, 1) = min(hi(1), floor((box(2, 1) - case%origin(1))/h))
            if (case%dim == 3) then
                range(1, 2) = max(lo(2), floor((box(1, 2) - case%origin(2))/h))
                range(2, 2) = min(hi(2), floor((box(2, 2) - case%origin(2))/h))
            else
                ! the line of a 2D case runs in the plane z = 0 (shifted)
                range(:, 2) = 0
                if (box(1, 2) > shift_v*h .or. box(2, 2) < shift_v*h) range(2, 2) = -1
            end if
            covered = all(range(1, :) <= range(2, :))
        end function covered

        !> Sorted heights (along w) of the crossings of the line through point with the
        !> triangles listed for column c.
        subroutine column_crossings(point, c, m)
            real(wp), intent(in) :: point(2)
                !! where the line crosses the (u, v) plane [m]
            integer, intent(in) :: c
                !! column
            integer, intent(out) :: m
                !! crossings found, in crossing(1:m)

            integer :: e, t, r
            real(wp) :: a(2), bb(2), cc(2), d(3), z

            m = 0
            do e = start(c), start(c + 1) - 1
                t = member(e)
                a = [triangle(1, 1, t), triangle(va, 1, t)]
                bb = [triangle(1, 2, t), triangle(va, 2, t)]
                cc = [triangle(1, 3, t), triangle(va, 3, t)]
                ! twice the signed areas of the sub-triangles opposite c, a and b
                d(1) = (bb(1) - a(1))*(point(2) - a(2)) - (bb(2) - a(2))*(point(1) - a(1))
                d(2) = (cc(1) - bb(1))*(point(2) - bb(2)) - (cc(2) - bb(2))*(point(1) - bb(1))
                d(3) = (a(1) - cc(1))*(point(2) - cc(2)) - (a(2) - cc(2))*(point(1) - cc(1))
                if (.not. (all(d > 0.0_wp) .or. all(d < 0.0_wp))) cycle
                z = (d(2)*triangle(wa, 1, t) + d(3)*triangle(wa, 2, t) &
                    + d(1)*triangle(wa, 3, t))/sum(d)
                ! insertion: the list stays sorted
                r = m
                do while (r > 0)
                    if (crossing(r) <= z) exit
                    crossing(r + 1) = crossing(r)
                    r = r - 1
                end do
                crossing(r + 1) = z
                m = m + 1
            end do
        end subroutine column_crossings

    end subroutine fill_surface

    !> Position of the particle of site p (index among the sites of all bodies, which seeds its
    !> jitter) in sub-cell s of spacing h.
    pure function particle_position(case, s, p, h) result(x)
        type(case_type), intent(in) :: case
            !! resolved case
        integer, intent(in) :: s(3)
            !! sub-cell along each axis (0 for unused axes)
        integer, intent(in) :: p
            !! site index
        real(wp), intent(in) :: h
            !! sub-cell size [m]
        real(wp) :: x(3)
            !! position (0 for unused axes) [m]

        integer :: a
        real(wp) :: jitter(3)

        jitter = 0.5_wp
        if (case%distribution == dist_random) then
            do a = 1, case%dim
                jitter(a) = uniform01(case%seed, p, a)
            end do
        end if
        x = 0.0_wp
        do a = 1, case%dim
            x(a) = case%origin(a) + (real(s(a), wp) + jitter(a))*h
        end do
    end function particle_position

    !> Cell (0-based, along axis a) of a coordinate in the whole grid, clamped to the grid
    !> (as mpm_decomposition's global_cell).
    pure integer function global_cell_of(case, x, a)
        type(case_type), intent(in) :: case
        real(wp), intent(in) :: x
        integer, intent(in) :: a
        global_cell_of = min(max(int((x - case%origin(a))/case%dx), 0), case%ncells(a) - 1)
    end function global_cell_of

    !> Reproducible uniform number in (0.05, 0.95) from (seed, particle, axis): splitmix64 hash.
    !>
    !> Independent of loop order and thread count; the margin keeps a particle off the
    !> faces of its sub-cell.
    pure real(wp) function uniform01(seed, p, axis)
        integer, intent(in) :: seed
            !! user seed
        integer, intent(in) :: p
            !! particle index
        integer, intent(in) :: axis
            !! coordinate axis

        integer(i8) :: z

        z = int(seed, i8)*1000003_i8 + int(p, i8)*3_i8 + int(axis, i8)
        z = z + (-7046029254386353131_i8)
        z = ieor(z, shiftr(z, 30))*(-4658895280553007687_i8)
        z = ieor(z, shiftr(z, 27))*(-7723592293110705685_i8)
        z = ieor(z, shiftr(z, 31))
        uniform01 = 0.05_wp + 0.9_wp*real(shiftr(z, 11), wp)/real(shiftl(1_i8, 53), wp)
    end function uniform01

end module mpm_bodies
