!> The `dimension` and `domain` keys of a case: the grid and its boundary conditions.
module mpm_case_domain
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: lower, int_text, fmt_real, int_list, same
    use mpm_json, only: json_is_valid, json_type_name, json_string
    use mpm_case_cursor, only: cursor_type, describe
    implicit none
    private
    public :: domain_section_type, read_domain, domain_keys, face_keys, face_object_keys
    public :: bc_free, bc_sliding, bc_fixed, bc_frictional, bc_names, axis_names

    ! Boundary condition of a domain face
    integer, parameter :: bc_free = 0     !! no constraint
    integer, parameter :: bc_sliding = 1  !! normal velocity zero, tangential free
    integer, parameter :: bc_fixed = 2    !! all velocity components zero (no slip, sticking)
    integer, parameter :: bc_frictional = 3
        !! Coulomb friction with coefficient mu; the material may separate from the face
    character(len=*), parameter :: bc_names(0:3) = [character(len=10) :: "free", "sliding", &
        "fixed", "frictional"]
        !! name of each boundary condition in the case file

    character(len=*), parameter :: domain_keys(*) = [character(len=10) :: "nx", "ny", "nz", &
        "dx", "origin", "boundaries"]
        !! keys of `domain`
    character(len=*), parameter :: face_keys(*) = [character(len=4) :: "xmin", "xmax", &
        "ymin", "ymax", "zmin", "zmax"]
        !! keys of `domain.boundaries`
    character(len=*), parameter :: face_object_keys(*) = [character(len=4) :: "type", "mu"]
        !! keys of a face given as an object
    character(len=*), parameter :: axis_names = "xyz"
        !! letter of each axis

    !> `domain`: the grid of cells and the condition of each of its faces.
    type :: domain_section_type
        integer :: ncells(3) = 1
            !! cells per direction (ncells(3) = 1 and unused in 2D)
        real(wp) :: dx = 0.0_wp
            !! cell size, equal in every direction [m]
        real(wp) :: origin(3) = 0.0_wp
            !! coordinates of the lowest domain corner [m]
        integer :: bc(2, 3) = bc_free
            !! boundary condition of each face: bc(1, axis) at the min face, bc(2, axis) at max
        real(wp) :: bc_friction(2, 3) = 0.0_wp
            !! Coulomb friction coefficient mu of each frictional face [-]
    end type domain_section_type

contains

    !> `dimension` and `domain`: the grid.
    subroutine read_domain(root, dim, domain, error)
        type(cursor_type), intent(in) :: root
            !! top-level object
        integer, intent(out) :: dim
            !! number of space dimensions
        type(domain_section_type), intent(inout) :: domain
            !! the domain section
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: cur
        logical :: has_nz
        integer :: d
        real(wp) :: nodes

        call root%get_section("domain", domain_keys, cur, error, required=.true.)
        if (allocated(error)) return
        has_nz = cur%has("nz")
        dim = merge(3, 2, has_nz)
        call root%get_int("dimension", dim, error, at_least=2, at_most=3)
        if (allocated(error)) return
        if (dim == 2 .and. has_nz) then
            call root%fail(error, "domain.nz is given but dimension = 2: remove " &
                //'domain.nz for a 2D case or set "dimension": 3')
            return
        end if
        if (dim == 3 .and. .not. has_nz) then
            call root%fail(error, "missing required key 'domain.nz' (an integer >= 1, " &
                //"cells along z): dimension = 3 needs it")
            return
        end if
        do d = 1, dim
            call cur%get_int("n"//axis_names(d:d), domain%ncells(d), error, required=.true., &
                at_least=1)
            if (allocated(error)) return
        end do
        ! the grid numbers its nodes with default integers
        nodes = product(real(domain%ncells(1:dim), wp) + 1.0_wp)
        if (nodes > real(huge(1), wp)) then
            call cur%fail(error, "domain: "//int_list(domain%ncells(1:dim), " x ") &
                //" cells make "//fmt_real(nodes, 3)//" nodes, more than the " &
                //int_text(huge(1))//" this version can number; use fewer cells (a larger dx)")
            return
        end if
        call cur%get_real("dx", domain%dx, error, required=.true., above=0.0_wp, unit="m")
        if (allocated(error)) return
        call cur%get_vector("origin", dim, domain%origin, error, unit="m")
        if (allocated(error)) return
        call read_boundaries(cur, dim, domain, error)
    end subroutine read_domain

    !> `domain.boundaries`: one condition per face.
    subroutine read_boundaries(cur, dim, domain, error)
        type(cursor_type), intent(in) :: cur
            !! the domain object
        integer, intent(in) :: dim
            !! number of space dimensions
        type(domain_section_type), intent(inout) :: domain
            !! the domain section
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: faces
        logical :: found
        integer :: k, axis, side

        call cur%get_section("boundaries", face_keys, faces, error, found=found)
        if (allocated(error) .or. .not. found) return
        do k = 1, size(face_keys)
            axis = (k + 1)/2
            side = 2 - mod(k, 2)
            if (axis > dim) then
                if (faces%has(trim(face_keys(k)))) then
                    call faces%fail(error, faces%key_path(trim(face_keys(k)))//" is not " &
                        //"allowed in a 2D case (dimension = 2): a 2D domain has no z faces")
                    return
                end if
                cycle
            end if
            call read_face(faces%child(trim(face_keys(k))), domain%bc(side, axis), &
                domain%bc_friction(side, axis), error)
            if (allocated(error)) return
        end do
    end subroutine read_boundaries

    !> One face of `domain.boundaries`: a name ("free", "sliding", "fixed") or an object
    !> {"type": ..., "mu": ...}; a frictional face is only written as an object, with its mu.
    subroutine read_face(face, bc, mu, error)
        type(cursor_type), intent(in) :: face
            !! the face's value (invalid when the face is not given)
        integer, intent(inout) :: bc
            !! condition of the face (unchanged when the face is not given)
        real(wp), intent(inout) :: mu
            !! Coulomb friction coefficient of a frictional face [-]
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        character(len=*), parameter :: frictional_form = '{"type": "frictional", "mu": 0.4}'
        character(len=*), parameter :: allowed = 'one of "free", "sliding", "fixed", or an ' &
            //"object "//frictional_form//" for a face with Coulomb friction"
        character(len=:), allocatable :: path, name
        integer :: i

        path = face%path
        if (.not. json_is_valid(face%obj)) return
        if (json_type_name(face%obj) == "string") then
            name = json_string(face%obj)
            do i = bc_free, bc_fixed
                if (same(lower(name), trim(bc_names(i)))) then
                    bc = i
                    return
                end if
            end do
            if (same(lower(name), trim(bc_names(bc_frictional)))) then
                call face%fail(error, path//' = "'//name//'" needs a friction ' &
                    //"coefficient: write the face as an object, "//frictional_form)
            else
                call face%fail(error, path//' = "'//name//'" is not allowed: must be ' &
                    //allowed)
            end if
            return
        end if
        if (json_type_name(face%obj) /= "object") then
            call face%fail(error, path//" has the wrong type: expected "//allowed &
                //", found "//describe(face%obj))
            return
        end if
        call face%check_keys(face_object_keys, error)
        if (allocated(error)) return
        call face%get_choice("type", bc_names, [bc_free, bc_sliding, bc_fixed, bc_frictional], &
            bc, error, required=.true.)
        if (allocated(error)) return
        if (bc == bc_frictional) then
            call face%get_real("mu", mu, error, required=.true., at_least=0.0_wp)
        else if (face%has("mu")) then
            call face%fail(error, path//".mu applies to frictional faces only (here " &
                //path//'.type = "'//trim(bc_names(bc))//'"); remove mu or set "type": ' &
                //'"frictional"')
        end if
    end subroutine read_face

end module mpm_case_domain
